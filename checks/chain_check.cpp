// Chained starts justified (the supplement's protocol and its Fig. SM-1b): each chained rate of
// a campaign (chain_phi_init) against the same rate compressed from phi_init without chaining,
// in a control directory (`--against`) holding the same samples of one size (the same seeds:
// the same random starts). Delta p/p over phi >= phi_min, with the statistics and margins of
// the phi_init check; phi_min is --phi-min, else the lower edge of the campaign's own scaling
// fit's window (what the fit uses must not remember the chain), else where both sets are past
// their starts' transients. pass: the data exclude an effect of the chain beyond the margin,
// so phi'_init is justified at that margin; fail: the chained start is remembered (phi'_init
// too close to jamming for that rate, outside the linear regime); inconclusive otherwise.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/regression_check.hpp"
#include "checks/relative_difference.hpp"

namespace jam::checks {
namespace {

using Key = std::tuple<std::int64_t, double, double>;  // n, phi_init, log10 rate

Key key_of(const EnsembleTables& e) {
  return {e.n, e.phi_init, e.log10_rate};
}

/// Fails v at the point where the chain's effect surely exceeds the margin, if there is one.
void fail_where_surely_beyond(Verdict& v, const RelativeDifference& r,
                              const std::vector<double>& grid, double margin) {
  std::size_t worst = r.delta.size();
  double beyond = margin;
  for (std::size_t k = 0; k < r.delta.size(); ++k) {
    const double low = std::abs(r.delta[k]) - r.critical * r.sigma[k];
    if (low > beyond) beyond = low, worst = k;
  }
  if (worst == r.delta.size()) return;
  v.status = "fail";
  v.samples_needed = NAN;
  v.reason = fmt::format(
      "at phi = {:.4f} the chain's effect surely exceeds the margin {:.3g}: Delta p/p = {:+.3g}, "
      "at least {:.3g} (simultaneous band, permutation p = {:.3g}); the weighted mean: {}",
      grid[r.points[worst]], margin, r.delta[worst], beyond, r.p_value, v.reason);
}

}  // namespace

std::vector<Verdict> chain_check(const StatsData& chained, const StatsData& control,
                                 const CheckOptions& o, const RegressionOptions&) {
  std::map<Key, const EnsembleTables*> unchained;
  for (const auto& e : control.ensembles)
    if (e.chain_phi_init == 0) unchained[key_of(e)] = &e;
  std::vector<std::pair<const EnsembleTables*, const EnsembleTables*>> pairs;
  for (const auto& e : chained.ensembles) {
    const auto it = unchained.find(key_of(e));
    if (e.chain_phi_init > 0 && it != unchained.end()) pairs.push_back({&e, it->second});
  }
  if (pairs.empty()) {
    return {inconclusive("chain", "all",
                         "no chained rate of the campaign has an unchained control (same size, "
                         "phi_init and rate) in the --against directory")};
  }
  const double alpha = o.alpha / static_cast<double>(pairs.size());
  const double margin = o.margin("chain");
  std::vector<Verdict> out;
  for (const auto& [e, c] : pairs) {
    Verdict v;
    v.check = "chain";
    const double compressed = std::max(e->compressed_from_phi, c->compressed_from_phi);
    const double phi_min =
        std::max(compressed, o.phi_min ? *o.phi_min : chained.fit_window_min.value_or(compressed));
    v.case_name = fmt::format(
        "n{} phi_init {:g} rate 1e{:g}: chained at {:g} vs unchained, "
        "phi >= {:.4f}",
        e->n, e->phi_init, e->log10_rate, e->chain_phi_init, phi_min);
    v.statistic_name = "|weighted mean Delta p/p|";
    v.values = {{"n", static_cast<double>(e->n)},
                {"phi_init", e->phi_init},
                {"log10_rate", e->log10_rate},
                {"chain_phi_init", e->chain_phi_init},
                {"phi_min", phi_min}};
    const Aligned al =
        align(e->phi_grid, e->pressure_at_phi, c->phi_grid, c->pressure_at_phi, phi_min);
    try {
      const WeightedDifference w = compare_weighted(al.a, al.b, alpha, o.permutations, 3);
      judge(v, w, alpha, margin, std::min(al.a.size(), al.b.size()));
      const RelativeDifference r = compare_run_sets(al.a, al.b, alpha, o.permutations, 3);
      v.values["pointwise_excluded_above"] = r.excluded_above;
      fail_where_surely_beyond(v, r, al.grid, margin);
      std::vector<double> grid;
      double weighted_phi = 0.0;  // where the verdict looks: the weights' mean packing
      for (std::size_t i = 0; i < r.points.size(); ++i) {
        grid.push_back(al.grid[r.points[i]]);
        weighted_phi += w.weight[i] * grid.back();
      }
      v.values["weighted_phi"] = weighted_phi;
      v.curves = {{"grid", grid}, {"delta", r.delta}, {"sigma", r.sigma}, {"weight", w.weight}};
    } catch (const std::invalid_argument& ex) {
      v.status = "inconclusive";
      v.reason = ex.what();
    }
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace jam::checks
