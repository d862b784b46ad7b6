// The paper's first result: below phi_J the compression is in linear response, p = zeta rate,
// with a bulk viscosity zeta(phi) that tends to a rate-independent value as rate -> 0. At each
// packing phi_J - 0.01 k (k = 1 ... 5, phi_J the campaign's own fit, nothing from the paper),
// zeta = p / rate at the two slowest rates of each (N, phi_init) is compared: pass when the
// data exclude a relative difference beyond the margin (zeta has converged there at these
// rates), fail when a larger one is detected (not yet rate-independent), inconclusive
// otherwise. One verdict per packing; the check's false-alarm rate is alpha (Bonferroni).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/relative_difference.hpp"

namespace jam::checks {
namespace {

/// Packings below phi_J at which zeta is compared: phi_J - 0.01 k, k = 1 ... 5.
constexpr int kPackings = 5;
constexpr double kPackingStep = 0.01;

struct Comparison {
  const EnsembleTables* slow;    // the slowest rate
  const EnsembleTables* faster;  // the next one
  double phi;                    // the packing compared (a grid point of both)
};

/// zeta = p / rate of every sample at the grid point nearest phi (within half a step), as a
/// [sample][1] table; empty when phi is off the grid or before the compression sets p.
std::vector<std::vector<double>> zeta_at(const EnsembleTables& e, double phi) {
  if (e.phi_grid.size() < 2 || phi < e.compressed_from_phi) return {};
  const double step = e.phi_grid[1] - e.phi_grid[0];
  const auto it = std::lower_bound(e.phi_grid.begin(), e.phi_grid.end(), phi - 0.5 * step);
  if (it == e.phi_grid.end() || std::abs(*it - phi) > 0.5 * step) return {};
  const auto k = static_cast<std::size_t>(it - e.phi_grid.begin());
  const double rate = std::pow(10.0, e.log10_rate);
  std::vector<std::vector<double>> out;
  for (const auto& row : e.pressure_at_phi) out.push_back({row[k] / rate});
  return out;
}

Verdict compare(const Comparison& c, double alpha, const CheckOptions& o) {
  Verdict v;
  v.check = "zeta";
  v.case_name =
      fmt::format("n{} phi_init {:g}, phi {:.4f}: zeta at rate 1e{:g} vs 1e{:g}", c.slow->n,
                  c.slow->phi_init, c.phi, c.slow->log10_rate, c.faster->log10_rate);
  v.statistic_name = "|Delta zeta/zeta| / sigma";
  v.margin = o.margin("zeta");
  v.values = {{"n", static_cast<double>(c.slow->n)},
              {"phi_init", c.slow->phi_init},
              {"phi", c.phi},
              {"log10_rate_slow", c.slow->log10_rate},
              {"log10_rate_faster", c.faster->log10_rate}};
  const auto a = zeta_at(*c.slow, c.phi), b = zeta_at(*c.faster, c.phi);
  if (a.size() < 2 || b.size() < 2) {
    v.status = "inconclusive";
    v.reason =
        "the packing is not on both grids past the start's transient, or fewer than 2 "
        "samples per rate";
    return v;
  }
  try {
    const RelativeDifference r = compare_run_sets(a, b, alpha, o.permutations);
    judge(v, r, alpha, o.margin("zeta"), std::min(a.size(), b.size()));
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
  std::vector<Comparison> comparisons;
  for (const auto& [key, rates] : by) {
    if (rates.size() < 2) continue;
    const auto slow = rates.begin(), faster = std::next(slow);
    for (int k = kPackings; k >= 1; --k)
      comparisons.push_back({slow->second, faster->second, *d.fit_phi_j - kPackingStep * k});
  }
  if (comparisons.empty()) {
    return {inconclusive("zeta", "all", "no (N, phi_init) has two rates")};
  }
  std::vector<Verdict> out;
  const double each = o.alpha / static_cast<double>(comparisons.size());
  for (const auto& c : comparisons) out.push_back(compare(c, each, o));
  return out;
}

}  // namespace jam::checks
