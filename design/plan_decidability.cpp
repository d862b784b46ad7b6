#include "design/plan_decidability.hpp"

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "campaign/added_samples.hpp"
#include "campaign/run_plan.hpp"
#include "checks/check_registry.hpp"
#include "checks/checks.hpp"
#include "checks/verdict_ensembles.hpp"
#include "checks/verdict_file.hpp"
#include "checks/window_scatter.hpp"
#include "sim/io/install_paths.hpp"
#include "sim/io/output_path.hpp"

namespace jam {
namespace {

struct ScatterPoint {
  double ln_n, log10_rate, ln_s2, dof;
};

/// Self-averaging: a window mean over N particles has a variance ~ 1/N, the exponent the fit
/// holds when its data have one size (reduced-2d's own fit finds -0.92).
constexpr double kHeldNExponent = -1.0;

ScatterFit fit(const std::vector<ScatterPoint>& p) {
  ScatterFit f;
  f.points = static_cast<int>(p.size());
  if (p.empty()) return f;
  f.n_min = f.rate_min = HUGE_VAL, f.n_max = f.rate_max = -HUGE_VAL;
  for (const auto& q : p) {
    f.n_min = std::min(f.n_min, std::exp(q.ln_n)), f.n_max = std::max(f.n_max, std::exp(q.ln_n));
    f.rate_min = std::min(f.rate_min, q.log10_rate);
    f.rate_max = std::max(f.rate_max, q.log10_rate);
  }
  // A coefficient the data cannot determine is held, not left to the solver: one size leaves
  // c1 free (held at kHeldNExponent), one rate c2 (held at 0, no rate dependence).
  f.n_exponent_held = f.n_max <= f.n_min * (1 + 1e-9);
  f.rate_slope_held = f.rate_max <= f.rate_min + 1e-9;
  const auto points = static_cast<Eigen::Index>(p.size());
  // Fewer points than coefficients (one verdict: two points) holds the rate slope, then the N
  // exponent; never a model left at zero (s = 1, thousands of samples "needed").
  if (points < 1 + !f.n_exponent_held + !f.rate_slope_held) f.rate_slope_held = true;
  if (points < 1 + !f.n_exponent_held + !f.rate_slope_held) f.n_exponent_held = true;
  const Eigen::Index free = 1 + !f.n_exponent_held + !f.rate_slope_held;
  Eigen::MatrixXd x(p.size(), free);
  Eigen::VectorXd y(p.size()), w(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    Eigen::Index col = 0;
    x(k, col++) = 1.0;
    if (!f.n_exponent_held) x(k, col++) = p[i].ln_n;
    if (!f.rate_slope_held) x(k, col++) = p[i].log10_rate;
    y(k) = p[i].ln_s2 - (f.n_exponent_held ? kHeldNExponent * p[i].ln_n : 0.0);
    w(k) = std::sqrt(p[i].dof);
  }
  const Eigen::MatrixXd xw = w.asDiagonal() * x;
  const Eigen::VectorXd c = xw.colPivHouseholderQr().solve(w.asDiagonal() * y);
  Eigen::Index col = 0;
  f.c0 = c(col++);
  f.c1 = f.n_exponent_held ? kHeldNExponent : c(col++);
  f.c2 = f.rate_slope_held ? 0.0 : c(col++);
  const Eigen::VectorXd r = y - x * c;
  // As many points as coefficients (a pilot of two sizes at one rate): the model passes
  // through them and has no residual to estimate.
  f.exact = points == free;
  if (f.exact) return f;
  double ss = 0, sw = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) ss += w(i) * w(i) * r(i) * r(i), sw += w(i) * w(i);
  f.residual = std::sqrt(ss / sw * static_cast<double>(points) /
                         static_cast<double>(points - free));
  return f;
}

/// values[key], NaN where the verdict has none.
double number(const std::map<std::string, double>& values, const char* key) {
  const auto it = values.find(key);
  return it == values.end() ? NAN : it->second;
}

}  // namespace

double ScatterFit::scatter(double n, double log10_rate) const {
  return std::sqrt(std::exp(c0 + c1 * std::log(n) + c2 * log10_rate));
}

std::vector<std::string> default_scatter_sources(int dim) {
  return {data_path(fmt::format("reference/results/reduced-{}d/checks.json", dim)).string()};
}

ScatterModel fit_scatter_model(const std::vector<std::string>& checks_files,
                               const std::string& region) {
  std::vector<ScatterPoint> at_phi, at_z;
  ScatterModel m;
  for (const auto& path : checks_files) {
    if (!std::filesystem::exists(path))
      throw std::runtime_error(path + ": not found (judge the campaign first: jam check all DIR)");
    const std::vector<checks::Verdict> verdicts = checks::read_verdict_file(path).verdicts;
    const std::size_t before = at_phi.size() + at_z.size();
    // The range asked, where the file judged it: its scatter, not that of a wider window.
    const bool of_region = !region.empty() && std::any_of(verdicts.begin(), verdicts.end(),
                                                          [&](const checks::Verdict& v) {
                                                            return v.region == region;
                                                          });
    for (const checks::Verdict& v : verdicts) {
      if (of_region && v.region != region) continue;
      const auto& x = v.values;
      const double rate = number(x, "log10_rate");
      const double na = std::isfinite(number(x, "n_a")) ? number(x, "n_a") : number(x, "n");
      const double nb = std::isfinite(number(x, "n_b")) ? number(x, "n_b") : number(x, "n");
      auto& into = number(x, "constant_z") == 1.0 ? at_z : at_phi;
      for (auto [n, s, k] : {std::tuple{na, number(x, "scatter_a"), number(x, "samples_a")},
                             std::tuple{nb, number(x, "scatter_b"), number(x, "samples_b")}}) {
        if (n > 0 && s > 0 && std::isfinite(s) && k >= 2 && std::isfinite(rate))
          into.push_back({std::log(n), rate, std::log(s * s), k - 1});
      }
    }
    if (at_phi.size() + at_z.size() == before) {
      throw std::runtime_error(fmt::format(
          "{}: no verdict with window scatter values (judge it with this jam: jam check all)",
          path));
    }
    m.sources.push_back(!region.empty() ? fmt::format("{} ({})", path,
                                                      of_region ? "its verdicts of the range asked"
                                                                : "it judged no range asked: its "
                                                                  "verdicts of wider ranges")
                                        : path);
  }
  m.at_phi = fit(at_phi);
  m.at_z = fit(at_z);
  return m;
}

namespace {

/// One comparison a check of the campaign will make.
struct Planned {
  std::string check;
  std::string kind;  // the check, with ", constant Z" or ", constant phi" where it says which
  bool at_z = false;
  EnsembleId a, b;
};

/// The comparisons every check the campaign asks for will make, as each declares them in its
/// registry line (verdict_ensembles.hpp): no check is named here.
std::vector<Planned> planned_comparisons(const Campaign& c) {
  std::vector<Planned> out;
  const auto& wanted = c.question.checks;  // empty: every check
  for (const checks::CheckEntry& e : checks::check_registry()) {
    const std::string name(e.name);
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) continue;
    for (const checks::Values& values : e.samples->planned(c)) {
      const std::vector<EnsembleId> ens = e.samples->ensembles(values);
      if (ens.size() != 2) continue;
      const auto z = values.find("constant_z");
      const bool at_z = z != values.end() && z->second == 1.0;
      const std::string kind = z == values.end() ? name
                               : at_z            ? name + ", constant Z"
                                                 : name + ", constant phi";
      out.push_back({name, kind, at_z, ens[0], ens[1]});
    }
  }
  return out;
}

using EnsembleKey = std::tuple<std::int64_t, double, double>;  // n, phi_init, log10 rate

EnsembleKey key(const EnsembleId& e) {
  return {e.n, e.phi_init, e.log10_rate};
}

}  // namespace

std::string planned_range_words(const Campaign& c) {
  if (c.question.states_range())
    return fmt::format("the range asked, phi in [{:g}, {:g}] ([question] phi_min, phi_max)",
                       *c.question.phi_min, *c.question.phi_max);
  // The scaling fit needs 3 rates (stats/fit_scan); without it the pooled verdicts pool
  // everything compressed.
  if (c.log10_rates.size() >= 3)
    return "the scaling fit's window (and the regions around its phi_J)";
  return fmt::format(
      "the whole compression, phi {:g} to {:g}: {} rates give no scaling fit and the campaign "
      "file states no range ([question] phi_min, phi_max)",
      *std::min_element(c.phi_init.begin(), c.phi_init.end()), c.run.phi_stop,
      c.log10_rates.size());
}

int print_decidability(const Campaign& c, const ScatterModel& model, const Throughput& speed) {
  fmt::print("  the verdicts judge {}\n", planned_range_words(c));
  const std::vector<Planned> planned = planned_comparisons(c);
  if (planned.empty()) {
    fmt::print("  what it can decide: no size or phi_init comparison (one size, one phi_init)\n");
    return 0;
  }
  const ScatterFit& shown = model.at_phi;
  fmt::print(
      "  what it can decide (window scatter ln s^2 = {:.2f} {:+.2f} ln N{} {:+.2f} log10 rate{} at "
      "constant phi, {}, from {}):\n",
      shown.c0, shown.c1, shown.n_exponent_held ? " (held: one size in the data)" : "", shown.c2,
      shown.rate_slope_held ? " (held: one rate in the data)" : "",
      shown.exact ? std::string("through its points exactly: no residual to estimate")
                  : fmt::format("residual factor {:.2f} on s", std::exp(shown.residual / 2)),
      fmt::join(model.sources, ", "));
  // Per-sample core-seconds of every ensemble (the cost of one more sample there).
  std::map<EnsembleKey, double> cost, runs;
  double planned_seconds = 0;
  for (const auto& r : plan_runs(c, SampleCounts{})) {  // the file's design, not the directory's
    const double seconds = speed.core_seconds(r.n, r.estimated_particle_steps);
    cost[{r.n, r.phi_init, r.log10_rate}] += seconds;
    runs[{r.n, r.phi_init, r.log10_rate}] += 1;
    planned_seconds += seconds;
  }
  for (auto& [k, s] : cost) s /= runs[k];
  std::map<std::string, int> count, decided;
  std::map<std::string, SampleCounts> want;  // samples per ensemble, per check
  std::map<std::string, double> most;
  const auto samples = static_cast<double>(c.samples);
  for (const auto& p : planned) ++count[p.kind];
  int warnings = 0;
  std::set<std::string> unmodelled;  // no verdict of that kind in the data: no scatter to use
  for (const auto& p : planned) {
    const std::string& kind = p.kind;
    const ScatterFit& f = p.at_z ? model.at_z : model.at_phi;
    if (f.points == 0) {
      unmodelled.insert(kind);
      continue;
    }
    const double margin =
        c.margins.contains(p.check) ? c.margins.at(p.check) : checks::default_margin(p.check);
    // Only the pass level matters here (a TOST at the check's alpha).
    const double z_pass =
        gsl_cdf_ugaussian_Qinv(c.question.alpha.value_or(checks::CheckOptions{}.alpha));
    const double sa = f.scatter(static_cast<double>(p.a.n), p.a.log10_rate),
                 sb = f.scatter(static_cast<double>(p.b.n), p.b.log10_rate);
    // With no effect, D ~ N(0, sigma) passes when |D| <= M - z_pass sigma: with probability
    // kPlanPower when sigma <= M / (z_pass + z), z the two-sided quantile of that power.
    const double target =
        margin / (z_pass + gsl_cdf_ugaussian_Qinv((1 - checks::kEstimatePower) / 2));
    if (std::sqrt((sa * sa + sb * sb) / samples) <= target) {
      ++decided[kind];
      continue;
    }
    const checks::SamplesNeeded n =
        checks::samples_for_sigma(target, sa, sb, cost[key(p.a)], cost[key(p.b)], samples, samples);
    most[kind] = std::max(most[kind], n.equal);
    for (const auto& [id, needed] : {std::pair{p.a, n.a}, std::pair{p.b, n.b}}) {
      auto& x = want[kind][id];
      x = std::max(x, static_cast<std::int64_t>(needed));
    }
  }
  for (const auto& [kind, total] : count) {
    if (unmodelled.contains(kind)) {
      ++warnings;
      fmt::print("    warning: {}: no verdict of its kind in {}: nothing to plan it from\n", kind,
                 fmt::join(model.sources, ", "));
      continue;
    }
    const int yes = decided[kind];
    if (yes == total) {
      fmt::print("    {}: all {} comparisons decide with {} samples\n", kind, total, c.samples);
      continue;
    }
    // The extra runs: the plan with these samples (on a chained campaign the faster rates
    // its runs continue from follow, samples_per_ensemble) less the plan as it is.
    double extra = -planned_seconds;
    for (const auto& r : plan_runs(c, samples_per_ensemble(c, want[kind])))
      extra += speed.core_seconds(r.n, r.estimated_particle_steps);
    ++warnings;
    fmt::print(
        "    warning: {}: {} of {} comparisons decide with {} samples; the other {} need up to "
        "{:.0f} samples per set (or the cheapest split per ensemble), about {:.2g} core-hours "
        "more\n",
        kind, yes, total, c.samples, total - yes, most[kind], extra / 3600.0);
  }
  for (const ScatterFit* f : {&model.at_phi, &model.at_z}) {
    const auto [lo, hi] = std::minmax_element(c.sizes.begin(), c.sizes.end());
    const auto [rlo, rhi] = std::minmax_element(c.log10_rates.begin(), c.log10_rates.end());
    if (static_cast<double>(*lo) < f->n_min * (1 - 1e-9) ||
        static_cast<double>(*hi) > f->n_max * (1 + 1e-9) || *rlo < f->rate_min - 1e-9 ||
        *rhi > f->rate_max + 1e-9) {
      fmt::print(
          "    (extrapolated: the model's data span N {:.0f}-{:.0f} and rates 1e{:g}-1e{:g}; a "
          "pilot at this design, --scatter-from DIR, measures it)\n",
          f->n_min, f->n_max, f->rate_min, f->rate_max);
      break;
    }
  }
  return warnings;
}

void print_phi_init_findings(const Campaign& c) {
  const std::filesystem::path file = std::filesystem::path(c.output) / "checks.json";
  if (!std::filesystem::exists(file)) return;
  try {
    for (const checks::Verdict& v : checks::read_verdict_file(file.string()).verdicts) {
      const auto& x = v.values;
      if (!x.contains("largest_consistent_phi_init")) continue;
      fmt::print(
          "  phi_init check (N {}, rate 1e{:g}): starting at phi_init {:g} instead of {:g} "
          "gives the same pressures and saves {:.0f}% of the compression time\n",
          number(x, "n"), number(x, "log10_rate"), number(x, "largest_consistent_phi_init"),
          number(x, "lowest_phi_init"), 100 * number(x, "compression_time_saved"));
    }
  } catch (const std::exception& e) {
    // read_verdict_file's reasons start with the file's name.
    fmt::print("  ({})\n", e.what());
  }
}

}  // namespace jam
