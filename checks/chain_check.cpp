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
#include "checks/pooled_verdict.hpp"
#include "checks/regression_check.hpp"
#include "checks/relative_difference.hpp"

namespace jam::checks {
std::vector<Verdict> chain_check(const StatsData& chained, const StatsData& control,
                                 const CheckOptions& o, const RegressionOptions&) {
  std::map<EnsembleKey, const EnsembleTables*> unchained;
  for (const auto& e : control.ensembles)
    if (e.chain_phi_init == 0) unchained[ensemble_key(e)] = &e;
  std::vector<std::pair<const EnsembleTables*, const EnsembleTables*>> pairs;
  for (const auto& e : chained.ensembles) {
    const auto it = unchained.find(ensemble_key(e));
    if (e.chain_phi_init > 0 && it != unchained.end()) pairs.push_back({&e, it->second});
  }
  if (pairs.empty()) {
    return {inconclusive("chain", "all",
                         "no chained rate of the campaign has an unchained control (same size, "
                         "phi_init and rate) in the --against directory")};
  }
  // Detection shared over every verdict: chained rates x (pooled + regions).
  const JammingReference jamming = jamming_reference(chained, o.phi_j);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const Levels levels{
      o.alpha / static_cast<double>(pairs.size() * verdicts_per_comparison(jamming, o.regions)),
      o.alpha};
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
    v.values = {{"n", static_cast<double>(e->n)},
                {"phi_init", e->phi_init},
                {"log10_rate", e->log10_rate},
                {"chain_phi_init", e->chain_phi_init},
                {"phi_min", phi_min}};
    PoolRange range;
    range.min = phi_min;
    range.why = o.phi_min ? "from --phi-min"
                : chained.fit_window_min
                    ? "from the campaign's scaling-fit window: what the fit uses must not "
                      "remember the chain"
                    : "no scaling fit: from where both sets are past their starts";
    range.pointwise_from = pointwise_start(false, *e, *c, compressed);
    const std::vector<PoolRange> regions =
        region_ranges(names, jamming, false, *e, *c, compressed, range.pointwise_from);
    const Aligned al =
        align(e->phi_grid, e->pressure_at_phi, c->phi_grid, c->pressure_at_phi, compressed);
    for (auto& x : judge_by_region(v, al, range, names, regions, levels, margin, o.permutations)) {
      if (x.values.count("weighted_at")) x.values["weighted_phi"] = x.values["weighted_at"];
      out.push_back(std::move(x));
    }
  }
  return out;
}

}  // namespace jam::checks
