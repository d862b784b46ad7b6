#include "checks/regression_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "checks/margin.hpp"
#include "checks/relative_difference.hpp"

namespace jam::checks {
namespace {

const EnsembleTables* find_match(const StatsData& d, const EnsembleTables& e) {
  for (const auto& x : d.ensembles) {
    if (x.n == e.n && std::abs(x.phi_init - e.phi_init) < 1e-9 &&
        std::abs(x.log10_rate - e.log10_rate) < 1e-9)
      return &x;
  }
  return nullptr;
}

// Largest relative difference between two curves of the same run on the common grid; a point
// finite in one and not in the other counts as an infinite difference.
double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::isnan(a[k]) && std::isnan(b[k])) continue;
    if (!std::isfinite(a[k]) || !std::isfinite(b[k]))
      return std::numeric_limits<double>::infinity();
    if (a[k] == b[k]) continue;
    worst = std::max(worst, std::abs(a[k] - b[k]) / std::max(std::abs(a[k]), std::abs(b[k])));
  }
  return worst;
}

Verdict rerun_verdict(const EnsembleTables& now, const EnsembleTables& base, const Aligned& al,
                      double tolerance) {
  Verdict v;
  v.check = "regression";
  v.case_name = case_label(now) + ": rerun samples identical to the baseline";
  v.statistic_name = "max |p_now / p_baseline - 1|";
  v.values = {{"n", static_cast<double>(now.n)},
              {"phi_init", now.phi_init},
              {"log10_rate", now.log10_rate}};
  double worst = 0.0;
  int compared = 0;
  std::int64_t worst_sample = 0;
  for (std::size_t i = 0; i < now.sample_ids.size(); ++i) {
    const auto it = std::find(base.sample_ids.begin(), base.sample_ids.end(), now.sample_ids[i]);
    if (it == base.sample_ids.end()) continue;
    const double d =
        largest_difference(al.a[i], al.b[static_cast<std::size_t>(it - base.sample_ids.begin())]);
    ++compared;
    if (d >= worst) {
      worst = d;
      worst_sample = now.sample_ids[i];
    }
  }
  if (compared == 0 || al.grid.empty()) {
    v.status = "inconclusive";
    v.reason = "no sample of the baseline was rerun (or no common grid points)";
    return v;
  }
  v.statistic = worst;
  v.threshold = tolerance;
  v.detectable = tolerance;
  v.margin = tolerance;  // deterministic: rerun samples reproduce within the tolerance, or not
  v.excluded_above = worst;
  v.status = worst <= tolerance ? "pass" : "fail";
  v.reason = fmt::format("{} rerun samples on {} grid points; largest difference {} (sample {})",
                         compared, al.grid.size(), effect_text(v, worst), worst_sample);
  return v;
}

}  // namespace

std::vector<Verdict> regression_check(const StatsData& now, const StatsData& baseline,
                                      const CheckOptions& o, const RegressionOptions& r) {
  if (now.dim != baseline.dim)
    return {
        inconclusive("regression", "all",
                     fmt::format("dimension {} against a {}D baseline", now.dim, baseline.dim))};
  struct Pair {
    const EnsembleTables* now;
    const EnsembleTables* base;
  };
  std::vector<Pair> pairs;
  std::vector<Verdict> out;
  for (const auto& e : now.ensembles) {
    if (const auto* b = find_match(baseline, e))
      pairs.push_back({&e, b});
    else
      out.push_back(inconclusive("regression", case_label(e), "the baseline has no such ensemble"));
  }
  // The statistical comparisons share alpha (Bonferroni over the ensembles with new samples).
  auto is_new = [](const EnsembleTables& base, std::int64_t id) {
    return std::find(base.sample_ids.begin(), base.sample_ids.end(), id) == base.sample_ids.end();
  };
  std::size_t with_new = 0;
  for (const auto& p : pairs) {
    std::size_t n_new = 0;
    for (auto id : p.now->sample_ids) n_new += is_new(*p.base, id);
    with_new += n_new >= 2;
  }
  const double alpha = o.alpha / static_cast<double>(std::max<std::size_t>(1, with_new));
  for (const auto& p : pairs) {
    // Rerun samples are compared everywhere; new samples from where the compression sets p.
    const Aligned all =
        align(p.now->phi_grid, p.now->pressure_at_phi, p.base->phi_grid, p.base->pressure_at_phi);
    out.push_back(rerun_verdict(*p.now, *p.base, all, r.tolerance));
    const Aligned al =
        align(p.now->phi_grid, p.now->pressure_at_phi, p.base->phi_grid, p.base->pressure_at_phi,
              std::max(p.now->compressed_from_phi, p.base->compressed_from_phi));
    std::vector<std::vector<double>> fresh;
    for (std::size_t i = 0; i < p.now->sample_ids.size(); ++i)
      if (is_new(*p.base, p.now->sample_ids[i])) fresh.push_back(al.a[i]);
    Verdict v;
    v.check = "regression";
    v.case_name = case_label(*p.now) + ": new samples against the baseline";
    v.statistic_name = "max |Delta p/p| / sigma";
    v.values = out.back().values;
    if (fresh.size() < 2 || al.b.size() < 2 || al.grid.empty()) {
      out.push_back(
          inconclusive("regression", v.case_name,
                       "fewer than 2 new samples (or 2 baseline samples) on a common grid"));
      continue;
    }
    try {
      const RelativeDifference t =
          compare_run_sets(fresh, al.b, Levels::two_sided(alpha), o.permutations);
      judge(v, t, Levels::two_sided(alpha), o.margin("regression"),
            std::min(fresh.size(), al.b.size()));
      v.curves = {{"grid", {}}, {"delta", t.delta}, {"sigma", t.sigma}};
      for (auto k : t.points) v.curves[0].second.push_back(al.grid[k]);
      v.reason =
          fmt::format("{} new vs {} baseline samples: ", fresh.size(), al.b.size()) + v.reason;
    } catch (const std::invalid_argument& e) {
      v = inconclusive("regression", v.case_name, e.what());
    }
    out.push_back(v);
  }
  if (out.empty()) return {inconclusive("regression", "all", "no ensembles to compare")};
  return out;
}

}  // namespace jam::checks
