// The paper's first result: below phi_J the compression is in linear response, p = zeta rate,
// with a bulk viscosity zeta(phi) that tends to a rate-independent value as rate -> 0. Over
// the packings phi_J - 0.05 ... phi_J - 0.01 (phi_J the campaign's own fit, nothing from the
// paper), zeta = p / rate at the two slowest rates of each (N, phi_init) is compared, pooled
// (checks/pooled_verdict.hpp): pass when the data exclude a relative difference beyond the
// margin (zeta has converged there at these rates), fail when a larger one is detected (not
// yet rate-independent), inconclusive otherwise. One verdict per (N, phi_init); the check's
// false-alarm rate is alpha (Bonferroni), each pass a two one-sided test at alpha.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/relative_difference.hpp"

namespace jam::checks {
namespace {

/// The packings below phi_J where zeta is compared: phi_J - 0.05 ... phi_J - 0.01. Below
/// phi_J - 0.01 the slowest rates are in linear response (the paper's Fig. 1: p / rate
/// collapses there); 0.05 keeps the range within the stored campaigns' compressed range.
constexpr double kNearest = 0.01, kFarthest = 0.05;

struct RatePair {
  const EnsembleTables* slow;    // the slowest rate
  const EnsembleTables* faster;  // the next one
};

/// zeta = p / rate: a pressure table divided by its rate.
std::vector<std::vector<double>> zeta_of(std::vector<std::vector<double>> p, double log10_rate) {
  const double rate = std::pow(10.0, log10_rate);
  for (auto& row : p)
    for (double& x : row) x /= rate;
  return p;
}

Verdict compare(const RatePair& c, double phi_j, Levels levels, const CheckOptions& o) {
  Verdict v;
  v.check = "zeta";
  PoolRange range;
  range.min =
      std::max({phi_j - kFarthest, c.slow->compressed_from_phi, c.faster->compressed_from_phi});
  range.max = phi_j - kNearest;
  range.why = "phi_J - 0.05 ... phi_J - 0.01 below the campaign's fitted phi_J, past the starts";
  v.case_name = fmt::format(
      "n{} phi_init {:g}, phi in [{:.4f}, {:.4f}]: zeta at rate 1e{:g} vs 1e{:g}", c.slow->n,
      c.slow->phi_init, range.min, range.max, c.slow->log10_rate, c.faster->log10_rate);
  v.values = {{"n", static_cast<double>(c.slow->n)},
              {"phi_init", c.slow->phi_init},
              {"log10_rate_slow", c.slow->log10_rate},
              {"log10_rate_faster", c.faster->log10_rate}};
  Aligned al = align(c.slow->phi_grid, c.slow->pressure_at_phi, c.faster->phi_grid,
                     c.faster->pressure_at_phi, range.min, range.max);
  if (al.grid.empty() || al.a.size() < 2 || al.b.size() < 2) {
    v.status = "inconclusive";
    v.reason = fmt::format(
        "no packing of both grids in [{:.4f}, {:.4f}] past the starts' transients, or fewer "
        "than 2 samples per rate",
        range.min, range.max);
    return v;
  }
  al.a = zeta_of(std::move(al.a), c.slow->log10_rate);
  al.b = zeta_of(std::move(al.b), c.faster->log10_rate);
  try {
    judge_pooled(v, al, range, levels, o.margin("zeta"), o.permutations);
    v.statistic_name = "|weighted mean Delta zeta/zeta|";
  } catch (const std::invalid_argument& e) {
    v.status = "inconclusive";
    v.reason = e.what();
  }
  return v;
}

}  // namespace

std::vector<Verdict> zeta_check(const StatsData& d, const CheckOptions& o) {
  if (!d.fit_phi_j || !std::isfinite(*d.fit_phi_j)) {
    return {inconclusive("zeta", "all",
                         "stats.h5 has no representative scaling fit: phi_J, and so which "
                         "packings lie below it, is unknown (the check uses the campaign's own "
                         "fit, never the paper's value)")};
  }
  std::map<std::pair<std::int64_t, double>, std::map<double, const EnsembleTables*>> by;
  for (const auto& e : d.ensembles) by[{e.n, e.phi_init}][e.log10_rate] = &e;
  std::vector<RatePair> comparisons;
  for (const auto& [key, rates] : by) {
    if (rates.size() < 2) continue;
    const auto slow = rates.begin(), faster = std::next(slow);
    comparisons.push_back({slow->second, faster->second});
  }
  if (comparisons.empty()) {
    return {inconclusive("zeta", "all", "no (N, phi_init) has two rates")};
  }
  std::vector<Verdict> out;
  const Levels levels{o.alpha / static_cast<double>(comparisons.size()), o.alpha};
  for (const auto& c : comparisons) out.push_back(compare(c, *d.fit_phi_j, levels, o));
  return out;
}

}  // namespace jam::checks
