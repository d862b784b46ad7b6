#include "checks/pooled_verdict.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "checks/margin.hpp"
#include "checks/window_scatter.hpp"

namespace jam::checks {
namespace {

/// Fails v at the point where the effect surely exceeds the margin, if there is one: its
/// simultaneous band (at the detection level) lies wholly beyond it.
void fail_where_surely_beyond(Verdict& v, const RelativeDifference& r,
                              const std::vector<double>& grid, const PoolRange& range,
                              double margin) {
  std::size_t worst = r.delta.size();
  double beyond = margin;
  for (std::size_t k = 0; k < r.delta.size(); ++k) {
    if (grid[r.points[k]] < range.pointwise_from) continue;
    const double low = std::abs(r.delta[k]) - r.critical * r.sigma[k];
    if (low > beyond) beyond = low, worst = k;
  }
  if (worst == r.delta.size()) return;
  v.status = "fail";
  v.samples_needed = NAN;
  // The verdict's numbers become the pointwise rule's, so that its interval speaks of one
  // effect: Delta p/p at the point where it surely exceeds the margin.
  v.excluded_below = beyond;
  v.excluded_above = std::max(beyond, r.excluded_above);
  v.estimate = r.delta[worst];
  v.values["pointwise_at"] = grid[r.points[worst]];
  // Its numbers are the row's (the tables put units in their headings, not in the rows).
  v.rule = fmt::format("the pointwise rule at {} {:.4f}, the numbers that point's", range.variable,
                       grid[r.points[worst]]);
  v.reason = fmt::format(
      "the effect surely exceeds the margin at {} = {:.4f}: Delta p/p = {}, at least {}, "
      "margin {} (simultaneous band, p = {:.3g}); the weighted mean: {}",
      range.variable, grid[r.points[worst]], effect_text(v, r.delta[worst], true),
      effect_text(v, beyond), effect_text(v, margin), r.p_value, v.reason);
}

/// The grid value below which `share` of the weight lies.
double weight_quantile(const std::vector<double>& grid, const std::vector<double>& weight,
                       double share) {
  double sum = 0.0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    sum += weight[k];
    if (sum >= share) return grid[k];
  }
  return grid.empty() ? NAN : grid.back();
}

}  // namespace

std::optional<PoolRange> phi_range(const StatsData& d, const CheckOptions& o, double compressed,
                                   bool need_fit, std::string* why_not) {
  PoolRange r;
  if (o.phi_min || o.phi_max) {
    r.min = o.phi_min.value_or(-HUGE_VAL);
    r.max = o.phi_max.value_or(HUGE_VAL);
    r.why = "the range given (--phi-min, --phi-max)";
  } else if (d.fit_window_min) {
    r.min = *d.fit_window_min;
    r.max = d.fit_window_max.value_or(HUGE_VAL);
    r.why = "the campaign's scaling-fit window, the data its fit uses";
  } else if (need_fit) {
    if (why_not) {
      *why_not =
          "stats.h5 has no scaling fit and no --phi-min was given: the range the fitted data "
          "need is unknown, and the start's own memory (before it) is not what this check "
          "asks";
    }
    return std::nullopt;
  } else {
    r.why = "no scaling fit in stats.h5: the whole compressed range";
    r.whole = true;
    r.no_regions_because = jamming_reference(d, o.phi_j).from;
  }
  if (compressed > r.min) {
    r.min = compressed;
    r.why += ", from where the compression sets both sets' pressure";
  }
  return r;
}

std::pair<double, double> z_span(const EnsembleTables& a, const EnsembleTables& b, double phi_lo,
                                 double phi_hi) {
  // Z values of each set whose mean packing is in [phi_lo, phi_hi]; the range both share.
  auto span = [&](const EnsembleTables& e, double* zmin, double* zmax) {
    *zmin = HUGE_VAL, *zmax = -HUGE_VAL;
    if (e.phi_at_z.size() != e.z_grid.size()) {
      *zmin = -HUGE_VAL, *zmax = HUGE_VAL;  // no mean packing stored: Z is not limited
      return;
    }
    for (std::size_t k = 0; k < e.z_grid.size(); ++k)
      if (e.phi_at_z[k] >= phi_lo && e.phi_at_z[k] <= phi_hi)
        *zmin = std::min(*zmin, e.z_grid[k]), *zmax = std::max(*zmax, e.z_grid[k]);
  };
  double amin = 0, amax = 0, bmin = 0, bmax = 0;
  span(a, &amin, &amax);
  span(b, &bmin, &bmax);
  return {std::max(amin, bmin), std::min(amax, bmax)};
}

Aligned cut(const Aligned& al, double lo, double hi) {
  Aligned out;
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < al.grid.size(); ++k)
    if (al.grid[k] >= lo - 1e-12 && al.grid[k] <= hi + 1e-12) keep.push_back(k);
  for (auto k : keep) out.grid.push_back(al.grid[k]);
  auto rows = [&keep](const std::vector<std::vector<double>>& in) {
    std::vector<std::vector<double>> t;
    for (const auto& r : in) {
      std::vector<double> x;
      for (auto k : keep) x.push_back(r[k]);
      t.push_back(std::move(x));
    }
    return t;
  };
  out.a = rows(al.a);
  out.b = rows(al.b);
  return out;
}

double pointwise_start(bool at_z, const EnsembleTables& a, const EnsembleTables& b,
                       double compressed_phi) {
  const double phi = compressed_phi + kStartTransient;
  if (!at_z) return phi;
  const double z = z_span(a, b, phi, HUGE_VAL).first;
  return std::isfinite(z) ? z : -HUGE_VAL;
}

std::vector<PoolRange> region_ranges(const std::vector<Region>& regions, const JammingReference& j,
                                     bool at_z, const EnsembleTables& a, const EnsembleTables& b,
                                     double compressed, double pointwise_from) {
  std::vector<PoolRange> out;
  for (const auto& g : regions) {
    PoolRange r;
    r.variable = at_z ? "Z" : "phi";
    std::tie(r.min, r.max) = at_z ? z_span(a, b, g.min, g.max) : std::pair{g.min, g.max};
    r.why = g.name == "asked" ? g.words() : fmt::format("{}, relative to {}", g.words(), j.from);
    if (at_z) r.why += ": the Z whose mean packing lies there";
    if (compressed > r.min) {
      r.min = compressed;
      r.why += ", from where the compression sets both sets' pressure";
    }
    r.pointwise_from = pointwise_from;
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<Verdict> judge_by_region(const Verdict& base, const Aligned& al,
                                     const PoolRange& pooled, const std::vector<Region>& names,
                                     const std::vector<PoolRange>& regions, Levels levels,
                                     double margin, int permutations, std::uint64_t seed,
                                     RelativeTo relative_to) {
  const RangeData data = [&al](const PoolRange& r, Verdict& v) {
    Aligned part = cut(al, r.min, r.max);
    if (part.grid.size() < 2) {
      v.reason = al.grid.empty() ? std::string("nothing")
                                 : fmt::format("{:.4g}, {:.4g}", al.grid.front(), al.grid.back());
    }
    return part;
  };
  return judge_by_region(base, data, pooled, names, regions, levels, margin, permutations, seed,
                         relative_to);
}

std::vector<Verdict> judge_by_region(const Verdict& base, const RangeData& data,
                                     const PoolRange& pooled, const std::vector<Region>& names,
                                     const std::vector<PoolRange>& regions, Levels levels,
                                     double margin, int permutations, std::uint64_t seed,
                                     RelativeTo relative_to) {
  std::vector<Verdict> out;
  auto one = [&](Verdict v, const PoolRange& range) {
    v.reason.clear();
    const Aligned part = data(range, v);
    try {
      if (!(range.min < range.max)) {
        throw std::invalid_argument(
            std::isfinite(range.min)
                ? fmt::format(
                      "nothing to judge: {} lies outside what both sets compress ({} from {:.4g})",
                      range.why, range.variable, range.min)
                : fmt::format("nothing to judge: no {} of both sets lies in {}", range.variable,
                              range.why));
      }
      if (part.grid.size() < 2) {
        // data() may say in the reason which range the compared data cover.
        // An empty span (no Z of both sets whose mean packing lies in the window) has no
        // finite ends: said in words, never as "[inf, -inf]".
        const std::string where =
            std::isfinite(range.min) && std::isfinite(range.max)
                ? fmt::format("in {} [{:.4g}, {:.4g}]", range.variable, range.min, range.max)
                : fmt::format("in {}: no {} of both sets lies in the range asked ({})",
                              range.variable, range.variable, range.why);
        throw std::invalid_argument(
            fmt::format("fewer than 2 common points {}{}", where,
                        v.reason.empty() ? "" : ": the compared data cover [" + v.reason + "]"));
      }
      judge_pooled(v, part, range, levels, margin, permutations, seed, relative_to);
    } catch (const std::invalid_argument& e) {
      v.status = "inconclusive";
      v.reason = e.what();
      v.margin = margin;
      v.curves.clear();
    }
    v.range_variable = range.variable;
    // The range asked, where the data did not reach it (judge_pooled keeps the range judged).
    if (std::isfinite(range.min)) v.values.insert({"range_min", range.min});
    if (std::isfinite(range.max)) v.values.insert({"range_max", range.max});
    out.push_back(std::move(v));
  };
  Verdict pooled_verdict = base;
  pooled_verdict.region = "pooled";
  one(pooled_verdict, pooled);
  say_if_whole(out.front(), pooled, !regions.empty());
  for (std::size_t i = 0; i < regions.size() && i < names.size(); ++i) {
    Verdict v = base;
    v.region = names[i].name;
    v.case_name += ", " + names[i].case_words();
    one(v, regions[i]);
  }
  return out;
}

void say_if_whole(Verdict& v, const PoolRange& pooled, bool regions_judged) {
  if (!pooled.whole || regions_judged) return;
  v.values["whole_compression"] = 1.0;
  v.reason += fmt::format(
      "; pooled over the whole compression: no range asked ([question] phi_min, phi_max or "
      "--phi-min, --phi-max) and {}",
      pooled.no_regions_because.empty() ? "no phi_J" : pooled.no_regions_because);
}

PoolRange z_range(const StatsData& d, const CheckOptions& o, const EnsembleTables& a,
                  const EnsembleTables& b, double compressed_z) {
  PoolRange r;
  r.variable = "Z";
  const auto lo = d.fit_z_window_min ? d.fit_z_window_min : d.fit_window_min;
  const auto hi = d.fit_z_window_max ? d.fit_z_window_max : d.fit_window_max;
  double phi_lo = -HUGE_VAL, phi_hi = HUGE_VAL;
  if (o.phi_min || o.phi_max) {
    phi_lo = o.phi_min.value_or(-HUGE_VAL), phi_hi = o.phi_max.value_or(HUGE_VAL);
    r.why = "the Z whose mean packing lies in the range given (--phi-min, --phi-max)";
  } else if (lo) {
    phi_lo = *lo, phi_hi = hi.value_or(HUGE_VAL);
    r.why = fmt::format("the Z whose mean packing lies in the {} fit's window",
                        d.fit_z_window_min ? "constant-Z" : "scaling");
  } else {
    r.why = "no scaling fit in stats.h5: the whole compressed range";
    r.whole = true;
    r.no_regions_because = jamming_reference(d, o.phi_j).from;
  }
  std::tie(r.min, r.max) = z_span(a, b, phi_lo, phi_hi);
  if (compressed_z > r.min) {
    r.min = compressed_z;
    r.why += ", from where the compression sets both sets' pressure";
  }
  return r;
}

void judge_pooled(Verdict& v, const Aligned& al, const PoolRange& range, Levels levels,
                  double margin, int permutations, std::uint64_t seed, RelativeTo relative_to) {
  v.statistic_name = "|weighted mean Delta p/p|";
  v.range_variable = range.variable;
  const WeightedDifference w =
      compare_weighted(al.a, al.b, levels, permutations, seed, relative_to);
  judge(v, w, levels, margin, std::min(al.a.size(), al.b.size()));
  // The estimate of samples comes from the window scatter (window_scatter.hpp), not from the
  // band of this one verdict: its words are replaced below.
  strip_samples_words(v.reason);
  v.samples_needed = NAN;
  const RelativeDifference r =
      compare_run_sets(al.a, al.b, levels, permutations, seed, relative_to);
  std::vector<double> grid;
  double at = 0.0;  // where the verdict looks: the weights' mean
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    grid.push_back(al.grid[r.points[i]]);
    at += w.weight[i] * grid.back();
  }
  const double from = weight_quantile(grid, w.weight, 0.1),
               to = weight_quantile(grid, w.weight, 0.9);
  v.reason += fmt::format(
      "; over {} in [{:.4g}, {:.4g}] ({}), weights centred at {} = {:.4g}, 80% "
      "of them in [{:.4g}, {:.4g}]",
      range.variable, grid.front(), grid.back(), range.why, range.variable, at, from, to);
  v.rule = "the weighted mean over the range";
  fail_where_surely_beyond(v, r, al.grid, range, margin);
  const WindowScatter scatter = window_scatter(al, w.points, w.weight);
  const auto n_a = static_cast<double>(al.a.size()), n_b = static_cast<double>(al.b.size());
  v.values["difference"] = w.difference;
  v.values["scatter_a"] = scatter.a;
  v.values["scatter_b"] = scatter.b;
  v.values["samples_a"] = n_a;
  v.values["samples_b"] = n_b;
  if (v.status == "inconclusive") {
    const SamplesNeeded n =
        samples_needed(w.difference, scatter.a, scatter.b, 1, 1, n_a, n_b, levels, margin);
    v.samples_needed = n.equal;
    v.values["samples_needed_a"] = n.a;
    v.values["samples_needed_b"] = n.b;
    v.reason += samples_words(n, "A", "B", false);
  }
  v.values["range_min"] = grid.front();
  v.values["range_max"] = grid.back();
  v.values["weighted_at"] = at;
  v.values["weight_from"] = from;
  v.values["weight_to"] = to;
  v.values["pointwise_excluded_above"] = r.excluded_above;
  v.curves = {{"grid", grid}, {"delta", r.delta}, {"sigma", r.sigma}, {"weight", w.weight}};
}

}  // namespace jam::checks
