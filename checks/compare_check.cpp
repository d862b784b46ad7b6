// Two campaigns of the same model, ensemble by ensemble: DIR (e.g. runs of another simulator)
// against REF (the reference simulator's campaign), whatever their sample counts, seeds and
// output grids (checks/compare_check.hpp). An ensemble of DIR is matched to one of REF with the
// same N, the same log10 rate (to 1e-9) and phi_init within 1e-6; ensembles of either without a
// partner are named in one inconclusive verdict.
//
//  compare: Delta p/p = (p_DIR - p_REF) / p_REF at constant phi and at constant Z, judged as
//    the pressure checks judge (checks/pooled_verdict.hpp: the inverse-variance weighted mean
//    over a stated range, its permutation null from relabelling whole runs, plus the pointwise
//    rule), relative to REF because REF is the standard. The range: --phi-min/--phi-max, else
//    REF's scaling-fit window, else from where both sets are past their compression transients
//    up to where half of REF's runs end; never shrunk to a short run's end: runs that end short
//    of it are left out by name, a pass over less than half of it is inconclusive, and output
//    far coarser than the grid is judged past the transient (checks/compare_coverage.hpp).
//    The grids: the values both share (multiples of a step) when there are at least two in the
//    range, else DIR's samples interpolated linearly onto REF's grid; the reason says which.
//    Detection at alpha / (comparisons), Bonferroni as finite_size; each pass a two one-sided
//    test at alpha.
//  compare_jamming: <phi_Ji> of DIR against REF, a permutation test of whole runs plus the two
//    one-sided tests (as phi_init's jamming_point), with both spreads in the reason.
//  compare_fit, compare_fit_phi_j: the per-(N, phi_init) fits of stats.h5 fit/families, beta
//    and y relative to REF's and phi_J as a packing difference, judged with Student's t as
//    fit_parameters judges them (checks/parameter_difference.hpp).
//  DIR and REF that are one campaign are refused (checks/same_campaign.hpp). Why they differ,
//  where it can tell (the models, the start, too few samples): checks/compare_diagnosis.hpp.
#include "checks/compare_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "checks/checks.hpp"
#include "checks/compare_coverage.hpp"
#include "checks/compare_diagnosis.hpp"
#include "checks/margin.hpp"
#include "checks/parameter_difference.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/regression_check.hpp"
#include "checks/relative_difference.hpp"
#include "checks/same_campaign.hpp"
#include "checks/window_scatter.hpp"

namespace jam::checks {
namespace {

constexpr double kRateTolerance = 1e-9;     // log10 rate: the same rate
constexpr double kPhiInitTolerance = 1e-6;  // phi_init: the same start, as written by either code

bool same_ensemble(const EnsembleTables& a, const EnsembleTables& b) {
  return a.n == b.n && std::abs(a.log10_rate - b.log10_rate) < kRateTolerance &&
         std::abs(a.phi_init - b.phi_init) < kPhiInitTolerance;
}

struct Pair {
  const EnsembleTables* dir;
  const EnsembleTables* ref;
};

/// The words of a range's reason, said of REF (phi_range and z_range speak of "the campaign").
std::string of_ref(std::string why) {
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"the campaign's scaling-fit window",
                                            "REF's scaling-fit window"},
        {"lies in the constant-Z fit's window", "lies in REF's constant-Z fit's window"},
        {"lies in the scaling fit's window", "lies in REF's scaling-fit window"},
        {"no scaling fit in stats.h5", "no scaling fit in REF's stats.h5"}}) {
    const auto at = why.find(from);
    if (at != std::string::npos) why.replace(at, from.size(), to);
  }
  return why;
}

/// How the grids were matched, in words for the reason.
std::string grid_words(const GridMatch& m, const std::string& variable) {
  const std::string steps =
      fmt::format("{}_step {:.3g} vs {:.3g}", variable, m.step_dir, m.step_ref);
  if (m.interpolated)
    return fmt::format(
        "DIR's samples interpolated linearly onto REF's grid ({}; {} grid value{} shared in the "
        "range, {} of REF's values compared)",
        steps, m.shared, m.shared == 1 ? "" : "s", m.aligned.grid.size());
  return fmt::format("on the {} grid values both grids share in the range ({})",
                     m.aligned.grid.size(), steps);
}

/// The pressure verdicts of one pair at constant phi or Z: pooled, and in the regions around
/// REF's phi_J; over REF's range, never shrunk to a short run's end (compare_coverage.hpp).
std::vector<Verdict> pressure_verdicts(const Pair& p, bool at_z, Levels levels,
                                       const StatsData& ref, const CheckOptions& o,
                                       const JammingReference& jamming) {
  Verdict v;
  v.check = "compare";
  v.case_name = fmt::format("{}: DIR vs REF, constant {}", case_label(*p.ref), at_z ? "Z" : "phi");
  v.values = {{"n", static_cast<double>(p.dir->n)},   {"n_a", static_cast<double>(p.dir->n)},
              {"n_b", static_cast<double>(p.ref->n)}, {"phi_init", p.ref->phi_init},
              {"log10_rate", p.ref->log10_rate},      {"constant_z", at_z ? 1.0 : 0.0}};
  const std::string variable = at_z ? "Z" : "phi";
  if (at_z && (p.dir->pressure_at_z.empty() || p.ref->pressure_at_z.empty())) {
    v.status = "inconclusive";
    v.region = "pooled";
    v.reason = fmt::format(
        "no constant-Z table in {}'s stats.h5 (its runs stored no contacts per particle, or "
        "`jam stats` made none)",
        p.dir->pressure_at_z.empty() && p.ref->pressure_at_z.empty() ? "DIR's nor REF"
        : p.dir->pressure_at_z.empty()                               ? "DIR"
                                                                     : "REF");
    return {v};
  }
  // Every run's data, also beyond where the shortest run ends.
  const EnsembleTables dir_all = widened(*p.dir), ref_all = widened(*p.ref);
  // From where the compression, not the start, sets the pressure in both sets.
  double from = at_z ? std::max(p.dir->compressed_from_z, p.ref->compressed_from_z)
                     : std::max(p.dir->compressed_from_phi, p.ref->compressed_from_phi);
  v.values["compared_from"] = from;
  PoolRange range =
      at_z ? z_range(ref, o, dir_all, ref_all, from) : *phi_range(ref, o, from, false, nullptr);
  range.why = of_ref(range.why);
  const double from_phi = std::max(p.dir->compressed_from_phi, p.ref->compressed_from_phi);
  range.pointwise_from = pointwise_start(at_z, dir_all, ref_all, from_phi);
  const std::string coarse = past_coarse_output(range, &from, at_z, dir_all, ref_all, from_phi, v);
  // REF's range ends where half of REF's runs end, not where its shortest does.
  const std::vector<double>& ref_grid = at_z ? ref_all.z_grid : ref_all.phi_grid;
  const double ref_end = typical_end(ref_all, at_z);
  if (std::isfinite(ref_end) && (at_z ? range.max > ref_end : !std::isfinite(range.max))) {
    range.max = ref_end;
    range.why +=
        fmt::format(", up to REF's end ({} {:.4g}, where half its runs reach)", variable, ref_end);
  }
  const CoveringRuns d = covering_runs(dir_all, at_z, range.min, range.max),
                     r = covering_runs(ref_all, at_z, range.min, range.max);
  v.values["left_out_dir"] = static_cast<double>(d.left_out.size());
  v.values["left_out_ref"] = static_cast<double>(r.left_out.size());
  const std::string left_out = left_out_words(d, r, range);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const std::vector<PoolRange> regions =
      region_ranges(names, jamming, at_z, d.tables, r.tables, from, range.pointwise_from);
  // Each range matches the grids within itself: another code's coarser grid is interpolated
  // onto REF's only where the two share too few values there.
  auto match = [&](const PoolRange& x_range) {
    return at_z ? match_grids(d.tables.z_grid, d.tables.pressure_at_z, r.tables.z_grid,
                              r.tables.pressure_at_z, x_range.min, x_range.max)
                : match_grids(d.tables.phi_grid, d.tables.pressure_at_phi, r.tables.phi_grid,
                              r.tables.pressure_at_phi, x_range.min, x_range.max);
  };
  std::map<std::string, std::string> words;  // by region
  const RangeData data = [&](const PoolRange& x_range, Verdict& x) {
    const GridMatch m = match(x_range);
    x.values["interpolated"] = m.interpolated ? 1.0 : 0.0;
    x.values["shared_points"] = static_cast<double>(m.shared);
    x.values["step_dir"] = m.step_dir;
    x.values["step_ref"] = m.step_ref;
    const std::string samples =
        fmt::format("DIR {} samples, REF {}", m.aligned.a.size(), m.aligned.b.size());
    words[x.region] = fmt::format("{}; {}", samples, grid_words(m, variable));
    for (const auto& more : {left_out, coarse})
      if (!more.empty()) words[x.region] += "; " + more;
    if (m.aligned.a.size() < 2 || m.aligned.b.size() < 2) return Aligned{};
    return m.aligned;
  };
  // The same grids again, for a verdict judged a second time past the start.
  const RangeData rejudge = [&](const PoolRange& x_range, Verdict&) {
    const GridMatch m = match(x_range);
    return m.aligned.a.size() < 2 || m.aligned.b.size() < 2 ? Aligned{} : m.aligned;
  };
  const double past_start =
      at_z ? z_span(d.tables, r.tables, -HUGE_VAL, from_phi + kStartSection).second
           : from_phi + kStartSection;
  const auto rows = [at_z](const EnsembleTables& e) {
    return (at_z ? e.pressure_at_z : e.pressure_at_phi).size();
  };
  const std::size_t n_dir = rows(d.tables), n_ref = rows(r.tables);
  const std::string too_few = too_few_samples(n_dir, n_ref);
  v.statistic_name = "|weighted mean (p_DIR - p_REF) / p_REF|";
  std::vector<Verdict> out = judge_by_region(v, data, range, names, regions, levels,
                                             o.margin("compare"), o.permutations, 3, RelativeTo::b);
  for (std::size_t k = 0; k < out.size(); ++k) {
    auto& x = out[k];
    x.statistic_name = v.statistic_name;
    x.reason += fmt::format(" ({})", words[x.region]);
    // The range asked of this verdict, within REF's data: a pass needs most of it judged.
    const PoolRange& asked = k == 0 ? range : regions[k - 1];
    const double asked_min = ref_grid.empty() ? asked.min : std::max(asked.min, ref_grid.front());
    const double asked_max = std::isfinite(ref_end) ? std::min(asked.max, ref_end) : asked.max;
    if (std::isfinite(asked_min)) x.values["asked_min"] = asked_min;
    if (std::isfinite(asked_max)) x.values["asked_max"] = asked_max;
    never_pass_narrow(x, asked_min, asked_max);
    if (!too_few.empty()) {
      // One run a side has no scatter to judge by: said with the counts, not as missing points.
      x.status = "inconclusive";
      x.reason = too_few + (left_out.empty() ? "" : "; " + left_out);
      x.samples_needed = NAN;
      x.values["samples_a"] = static_cast<double>(n_dir);
      x.values["samples_b"] = static_cast<double>(n_ref);
    } else {
      say_if_only_at_start(x, asked, past_start, rejudge, levels, o.margin("compare"),
                           o.permutations);
    }
  }
  return out;
}

/// Sample standard deviation of the finite values (NaN with fewer than two).
double spread(const std::vector<double>& x, std::size_t* count) {
  double mean = 0, ss = 0;
  std::size_t n = 0;
  for (double y : x)
    if (std::isfinite(y)) mean += y, ++n;
  *count = n;
  if (n < 2) return NAN;
  mean /= static_cast<double>(n);
  for (double y : x)
    if (std::isfinite(y)) ss += (y - mean) * (y - mean);
  return std::sqrt(ss / static_cast<double>(n - 1));
}

/// <phi_Ji> of DIR against REF.
Verdict jamming_verdict(const Pair& p, Levels levels, const CheckOptions& o) {
  Verdict j;
  j.check = "compare_jamming";
  j.case_name = fmt::format("{}: <phi_Ji> DIR vs REF", case_label(*p.ref));
  j.statistic_name = "|<phi_Ji>_DIR - <phi_Ji>_REF| / sigma";
  j.values = {{"n", static_cast<double>(p.dir->n)},
              {"phi_init", p.ref->phi_init},
              {"log10_rate", p.ref->log10_rate},
              {"constant_z", 0.0}};
  std::size_t n_dir = 0, n_ref = 0;
  const double s_dir = spread(p.dir->jamming_points, &n_dir),
               s_ref = spread(p.ref->jamming_points, &n_ref);
  j.values["spread_dir"] = s_dir;
  j.values["spread_ref"] = s_ref;
  const std::string spreads = fmt::format(
      "spread of phi_Ji (standard deviation): DIR {:.3g} over {} runs, REF {:.3g} over {} runs",
      s_dir, n_dir, s_ref, n_ref);
  if (const auto few = too_few_samples(n_dir, n_ref, " with a jamming point"); !few.empty()) {
    Verdict x = inconclusive("compare_jamming", j.case_name, fmt::format("{} ({})", few, spreads));
    x.values = j.values;
    return x;
  }
  try {
    const MeanDifference m =
        compare_means(p.dir->jamming_points, p.ref->jamming_points, levels, o.permutations, 4);
    judge(j, m, levels, o.margin("compare_jamming"), std::min(n_dir, n_ref));
    j.values["difference"] = m.difference;
    j.reason += "; " + spreads;
  } catch (const std::invalid_argument& e) {
    j = inconclusive("compare_jamming", j.case_name,
                     fmt::format("{} ({}; NaN: no jamming point found)", e.what(), spreads));
  }
  return j;
}

/// The fitted parameters of each (N, phi_init) both campaigns fitted.
void compare_fits(const StatsData& dir, const StatsData& ref, const CheckOptions& o,
                  std::vector<Verdict>& out) {
  if (dir.families.empty() || ref.families.empty()) {
    const std::string which = dir.families.empty() && ref.families.empty() ? "DIR's nor REF's"
                              : dir.families.empty()                       ? "DIR's"
                                                                           : "REF's";
    const std::string why = fmt::format(
        "no per-size fits (fit/families) in {} stats.h5: no representative scaling fit, or "
        "written by an older jam (rerun `jam stats`)",
        which);
    out.push_back(inconclusive("compare_fit", "all", why));
    out.push_back(inconclusive("compare_fit_phi_j", "all", why));
    return;
  }
  auto name = [](const FamilyParameters& f) {
    return fmt::format("n{} phi_init {:g}", f.n, f.phi_init);
  };
  std::vector<std::pair<const FamilyParameters*, const FamilyParameters*>> pairs;
  std::vector<bool> ref_matched(ref.families.size(), false);
  std::string dir_only, ref_only;
  for (const auto& f : dir.families) {
    const FamilyParameters* partner = nullptr;
    for (std::size_t k = 0; k < ref.families.size() && !partner; ++k) {
      const auto& g = ref.families[k];
      if (g.n == f.n && std::abs(g.phi_init - f.phi_init) < kPhiInitTolerance) {
        partner = &g;
        ref_matched[k] = true;
      }
    }
    if (partner)
      pairs.push_back({&f, partner});
    else
      dir_only += (dir_only.empty() ? "" : ", ") + name(f);
  }
  for (std::size_t k = 0; k < ref.families.size(); ++k)
    if (!ref_matched[k]) ref_only += (ref_only.empty() ? "" : ", ") + name(ref.families[k]);
  std::size_t fitted = 0;
  for (const auto& [a, b] : pairs) fitted += a->failure.empty() && b->failure.empty();
  const double detect = o.alpha / static_cast<double>(std::max<std::size_t>(1, fitted));
  for (const auto& [a, b] : pairs) {
    const std::string what = name(*b) + ": DIR vs REF";  // named by REF's start
    const std::map<std::string, double> values = {{"n", static_cast<double>(a->n)},
                                                  {"phi_init", b->phi_init}};
    if (!a->failure.empty() || !b->failure.empty()) {
      const std::string why =
          !a->failure.empty() ? "no fit in DIR: " + a->failure : "no fit in REF: " + b->failure;
      out.push_back(inconclusive("compare_fit", "exponents, " + what, why));
      out.back().values = values;
      out.push_back(inconclusive("compare_fit_phi_j", "phi_J, " + what, why));
      out.back().values = values;
      continue;
    }
    // Relative to REF's value, as the pressures: Delta = a / b - 1.
    auto relative = [](const char* parameter, double x, double ex, double y, double ey) {
      const double ratio = x / y;
      return ParameterDifference{parameter, x, y, ratio - 1,
                                 std::sqrt(ex * ex + ratio * ratio * ey * ey) / std::abs(y)};
    };
    const std::int64_t samples = std::min(a->samples, b->samples);
    Verdict exponents =
        judge_parameters("compare_fit", "exponents, " + what,
                         {relative("beta", a->beta, a->beta_err, b->beta, b->beta_err),
                          relative("y", a->y, a->y_err, b->y, b->y_err)},
                         samples, detect, o.alpha, o.margin("compare_fit"));
    Verdict phi_j = judge_parameters("compare_fit_phi_j", "phi_J, " + what,
                                     {{"phi_J", a->phi_j, b->phi_j, a->phi_j - b->phi_j,
                                       std::hypot(a->phi_j_err, b->phi_j_err)}},
                                     samples, detect, o.alpha, o.margin("compare_fit_phi_j"));
    exponents.values = values;
    phi_j.values = values;
    out.push_back(std::move(exponents));
    out.push_back(std::move(phi_j));
  }
  if (!dir_only.empty() || !ref_only.empty()) {
    out.push_back(inconclusive(
        "compare_fit", "fits without a partner",
        fmt::format("not compared: fitted in DIR only: {}; fitted in REF only: {}",
                    dir_only.empty() ? "none" : dir_only, ref_only.empty() ? "none" : ref_only)));
  }
}

}  // namespace

double grid_step(const std::vector<double>& grid) {
  std::vector<double> steps;
  for (std::size_t k = 1; k < grid.size(); ++k)
    if (grid[k] > grid[k - 1]) steps.push_back(grid[k] - grid[k - 1]);
  if (steps.empty()) return NAN;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

GridMatch match_grids(const std::vector<double>& grid_dir,
                      const std::vector<std::vector<double>>& dir,
                      const std::vector<double>& grid_ref,
                      const std::vector<std::vector<double>>& ref, double min, double max) {
  GridMatch m;
  m.step_dir = grid_step(grid_dir);
  m.step_ref = grid_step(grid_ref);
  Aligned shared = align(grid_dir, dir, grid_ref, ref, min, max);
  m.shared = shared.grid.size();
  if (m.shared >= 2) {
    m.aligned = std::move(shared);
    return m;
  }
  m.interpolated = true;
  // REF's grid values in the range and within DIR's grid: the DIR point below each and the
  // fraction of the way to the next.
  std::vector<std::size_t> ref_index, below;
  std::vector<double> fraction;
  constexpr double kSlack = 1e-12;
  for (std::size_t k = 0; k < grid_ref.size() && grid_dir.size() >= 2; ++k) {
    const double g = grid_ref[k];
    if (g < min - kSlack || g > max + kSlack) continue;
    if (g < grid_dir.front() - kSlack || g > grid_dir.back() + kSlack) continue;
    std::size_t j = static_cast<std::size_t>(std::upper_bound(grid_dir.begin(), grid_dir.end(), g) -
                                             grid_dir.begin());
    j = std::min(j == 0 ? 0 : j - 1, grid_dir.size() - 2);
    const double width = grid_dir[j + 1] - grid_dir[j];
    if (!(width > 0)) continue;
    ref_index.push_back(k);
    below.push_back(j);
    fraction.push_back(std::clamp((g - grid_dir[j]) / width, 0.0, 1.0));
    m.aligned.grid.push_back(g);
  }
  for (const auto& row : dir) {
    std::vector<double> x;
    for (std::size_t i = 0; i < below.size(); ++i) {
      const double f = fraction[i], lo = row[below[i]], hi = row[below[i] + 1];
      // At a grid value of DIR the value itself (a NaN next to it does not spread).
      x.push_back(f == 0.0 ? lo : f == 1.0 ? hi : (1 - f) * lo + f * hi);
    }
    m.aligned.a.push_back(std::move(x));
  }
  for (const auto& row : ref) {
    std::vector<double> x;
    for (auto k : ref_index) x.push_back(row[k]);
    m.aligned.b.push_back(std::move(x));
  }
  return m;
}

std::vector<Verdict> compare_check(const StatsData& dir, const StatsData& ref,
                                   const CheckOptions& o, const RegressionOptions&) {
  refuse_same_campaign(dir, ref);
  if (dir.dim != ref.dim)
    return {inconclusive("compare", "all",
                         fmt::format("DIR is {}D, REF {}D: nothing to compare", dir.dim, ref.dim))};
  if (dir.ensembles.empty() && ref.ensembles.empty()) {
    std::vector<Verdict> out = {
        inconclusive("compare", "all", "neither stats.h5 has an ensemble: no pressure to compare")};
    compare_fits(dir, ref, o, out);
    return out;
  }
  std::vector<Pair> pairs;
  std::vector<bool> ref_matched(ref.ensembles.size(), false);
  std::string dir_only, ref_only;
  std::size_t unmatched = 0;
  for (const auto& e : dir.ensembles) {
    const EnsembleTables* partner = nullptr;
    for (std::size_t k = 0; k < ref.ensembles.size() && !partner; ++k) {
      if (!ref_matched[k] && same_ensemble(e, ref.ensembles[k])) {
        partner = &ref.ensembles[k];
        ref_matched[k] = true;
      }
    }
    if (partner) {
      pairs.push_back({&e, partner});
    } else {
      dir_only += (dir_only.empty() ? "" : ", ") + case_label(e);
      ++unmatched;
    }
  }
  for (std::size_t k = 0; k < ref.ensembles.size(); ++k) {
    if (ref_matched[k]) continue;
    ref_only += (ref_only.empty() ? "" : ", ") + case_label(ref.ensembles[k]);
    ++unmatched;
  }
  // Bonferroni over the comparisons made: constant phi for every pair, constant Z where both
  // have its table; the jamming points apart, over the pairs that carry them.
  std::size_t comparisons = 0, jamming = 0;
  auto has_jamming = [](const EnsembleTables& e) {
    return std::any_of(e.jamming_points.begin(), e.jamming_points.end(),
                       [](double x) { return std::isfinite(x); });
  };
  for (const auto& p : pairs) {
    comparisons += 1 + (!p.dir->pressure_at_z.empty() && !p.ref->pressure_at_z.empty());
    jamming += has_jamming(*p.dir) && has_jamming(*p.ref);
  }
  // ... and over the regions around REF's phi_J, beside each pooled verdict.
  const JammingReference jamming_ref = jamming_reference(ref, o.phi_j);
  const Levels levels{
      o.alpha / static_cast<double>(std::max<std::size_t>(1, comparisons) *
                                    verdicts_per_comparison(jamming_ref, o.regions)),
      o.alpha};
  const Levels jamming_levels{o.alpha / static_cast<double>(std::max<std::size_t>(1, jamming)),
                              o.alpha};
  std::vector<Verdict> out;
  std::vector<ScatterSeries> series;  // the samples estimate pools each series over its rates
  std::map<std::tuple<std::int64_t, double, bool, std::string>, int> series_of;
  for (const auto& p : pairs) {
    for (bool at_z : {false, true}) {
      for (auto& v : pressure_verdicts(p, at_z, levels, ref, o, jamming_ref)) {
        out.push_back(std::move(v));
        if (!out.back().values.count("scatter_a")) continue;
        const auto key = std::tuple{p.ref->n, p.ref->phi_init, at_z, out.back().region};
        const int id = series_of.emplace(key, static_cast<int>(series_of.size())).first->second;
        series.push_back({out.size() - 1, id, p.ref->log10_rate, 1.0, 1.0, "DIR", "REF"});
      }
    }
    const bool dir_j = has_jamming(*p.dir), ref_j = has_jamming(*p.ref);
    if (dir_j && ref_j) {
      out.push_back(jamming_verdict(p, jamming_levels, o));
    } else if (dir_j || ref_j) {
      out.push_back(inconclusive(
          "compare_jamming", fmt::format("{}: <phi_Ji> DIR vs REF", case_label(*p.ref)),
          fmt::format("only {} carries jamming points (phi_Ji found in its runs): nothing to "
                      "compare them with",
                      dir_j ? "DIR" : "REF")));
      out.back().values = {{"n", static_cast<double>(p.dir->n)},
                           {"phi_init", p.ref->phi_init},
                           {"log10_rate", p.ref->log10_rate},
                           {"constant_z", 0.0}};
    }
  }
  if (unmatched > 0 || pairs.empty()) {
    Verdict v = inconclusive(
        "compare", "ensembles without a partner",
        fmt::format("not compared (a partner has the same N, the same rate and phi_init within "
                    "{:g}): in DIR only: {}; in REF only: {}",
                    kPhiInitTolerance, dir_only.empty() ? "none" : dir_only,
                    ref_only.empty() ? "none" : ref_only));
    v.values = {{"unmatched", static_cast<double>(unmatched)},
                {"matched", static_cast<double>(pairs.size())}};
    out.push_back(std::move(v));
  }
  pool_window_scatter(out, series, o.for_estimate(levels), o.margin("compare"));
  compare_fits(dir, ref, o, out);
  name_model_difference(out, campaign_model(dir.directory), campaign_model(ref.directory));
  return out;
}

}  // namespace jam::checks
