// Independence of phi_init (the paper's supplement, "Compression Protocol"): Delta p/p between
// runs started at each phi_init and runs started at the lowest one, same size and rate, pooled
// over the scaling fit's window (checks/pooled_verdict.hpp) or --phi-min/--phi-max, since
// independence of the start is what the fitted data need, and in the regions below, at and
// above jamming (checks/regions.hpp). Without a fit or a range the
// verdicts are inconclusive and say why: just past the higher start its pressure still
// carries the start's own memory, and a comparison there failed at -182% on what no fit uses
// (never past where the compression, not the start, sets the pressure: margin.hpp). Memory of
// the random start fades
// at slower rates, so the verdicts are per rate; each summary says the largest phi_init still
// consistent with the lowest and the share of compression time that starting there saves.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/relative_difference.hpp"
#include "checks/window_scatter.hpp"

namespace jam::checks {
namespace {
double alpha_jamming(const CheckOptions& o, std::size_t comparisons) {
  return o.alpha / static_cast<double>(std::max<std::size_t>(1, comparisons));
}
}  // namespace

std::vector<Verdict> phi_init_check(const StatsData& d, const CheckOptions& o) {
  const double margin = o.margin("phi_init"), jamming_margin = o.margin("jamming_point");
  // (n, rate) -> phi_init -> ensemble
  std::map<std::pair<std::int64_t, double>, std::map<double, const EnsembleTables*>> by;
  for (const auto& e : d.ensembles) by[{e.n, e.log10_rate}][e.phi_init] = &e;
  std::size_t comparisons = 0;
  for (const auto& [key, starts] : by) comparisons += starts.size() - 1;
  std::size_t jamming_comparisons = 0;
  for (const auto& [key, starts] : by)
    for (const auto& [phi, e] : starts)
      jamming_comparisons += !e->jamming_points.empty() && phi != starts.begin()->first &&
                             !starts.begin()->second->jamming_points.empty();
  if (comparisons == 0)
    return {inconclusive("phi_init", "all", "the campaign has a single phi_init")};
  // Detection shared over every verdict: comparisons x (pooled + regions).
  const JammingReference jamming = jamming_reference(d, o.phi_j);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const Levels levels{
      o.alpha / static_cast<double>(comparisons * verdicts_per_comparison(jamming, o.regions)),
      o.alpha};
  std::vector<Verdict> out;
  std::vector<ScatterSeries> series;  // the samples estimate pools over rates
  std::map<std::tuple<std::int64_t, double, std::string>, int> series_of;
  for (const auto& [key, starts] : by) {
    const auto* low = starts.begin()->second;
    double largest_consistent = low->phi_init;
    bool all_consistent_so_far = true;
    for (auto it = std::next(starts.begin()); it != starts.end(); ++it) {
      const auto* e = it->second;
      Verdict v;
      v.check = "phi_init";
      const double compressed = std::max(e->compressed_from_phi, low->compressed_from_phi);
      std::string why_not;
      std::optional<PoolRange> range = phi_range(d, o, compressed, true, &why_not);
      v.case_name = fmt::format("n{} rate 1e{:g}: phi_init {:g} vs {:g}", key.first, key.second,
                                e->phi_init, low->phi_init);
      v.values = {{"n", static_cast<double>(key.first)},
                  {"log10_rate", key.second},
                  {"phi_init", e->phi_init},
                  {"lowest_phi_init", low->phi_init}};
      const double pointwise_from = pointwise_start(false, *e, *low, compressed);
      const std::vector<PoolRange> regions =
          region_ranges(names, jamming, false, *e, *low, compressed, pointwise_from);
      const Aligned al = align(e->phi_grid, e->pressure_at_phi, low->phi_grid, low->pressure_at_phi,
                               compressed, HUGE_VAL);
      PoolRange pooled = range.value_or(PoolRange{});
      pooled.pointwise_from = pointwise_from;
      std::vector<Verdict> judged =
          judge_by_region(v, al, pooled, names, regions, levels, margin, o.permutations);
      if (!range) {
        // No fit and no range given: the pooled verdict has nothing it may judge; the
        // regions (placed by <phi_Ji> or --phi-j) still stand.
        judged.front() = v;
        judged.front().region = "pooled";
        judged.front().status = "inconclusive";
        judged.front().reason = why_not;
      }
      // Consistent only where the data exclude effects beyond the margin, in every range the
      // data cover (a region beyond them has nothing to judge and says nothing against it).
      for (const auto& x : judged) {
        const bool uncovered = x.region != "pooled" && x.reason.starts_with("nothing to judge");
        if (x.status != "pass" && !uncovered) all_consistent_so_far = false;
      }
      if (all_consistent_so_far) largest_consistent = e->phi_init;
      const std::size_t first = out.size();
      for (auto& x : judged) out.push_back(std::move(x));
      // One series per (N, phi_init pair, region): the same samples' cost in both sets.
      for (std::size_t i = first; i < out.size(); ++i) {
        const auto id = series_of.emplace(std::tuple{key.first, e->phi_init, out[i].region},
                                          static_cast<int>(series_of.size()));
        series.push_back({i, id.first->second, key.second, 1.0, 1.0,
                          fmt::format("phi_init {:g}", e->phi_init),
                          fmt::format("phi_init {:g}", low->phi_init)});
      }
      // The jamming points themselves, when the runs looked for them.
      if (!e->jamming_points.empty() && !low->jamming_points.empty()) {
        Verdict j;
        j.check = "jamming_point";
        j.case_name = fmt::format("n{} rate 1e{:g}: <phi_Ji> at phi_init {:g} vs {:g}", key.first,
                                  key.second, e->phi_init, low->phi_init);
        j.statistic_name = "|<phi_Ji>_a - <phi_Ji>_b| / sigma";
        j.values = v.values;
        try {
          const Levels a_j{alpha_jamming(o, jamming_comparisons), o.alpha};
          const MeanDifference m =
              compare_means(e->jamming_points, low->jamming_points, a_j, o.permutations, 4);
          judge(j, m, a_j, jamming_margin,
                std::min(e->jamming_points.size(), low->jamming_points.size()));
        } catch (const std::invalid_argument& ex) {
          j = inconclusive("jamming_point", j.case_name, ex.what());
        }
        out.push_back(j);
      }
    }
    // Compression time from phi0 to phi_stop is ln(phi_stop / phi0) / (D rate).
    const double phi_stop = low->phi_grid.empty() ? 0 : low->phi_grid.back();
    const double saved =
        std::log(largest_consistent / low->phi_init) / std::log(phi_stop / low->phi_init);
    out.back().reason += fmt::format(
        " | n{} rate 1e{:g}: largest phi_init consistent with {:g} within {} is {:g} "
        "(saves {:.0f}% of the compression time)",
        key.first, key.second, low->phi_init, effect_text("relative", margin), largest_consistent,
        100 * saved);
    out.back().values.insert({{"n", static_cast<double>(key.first)},
                              {"log10_rate", key.second},
                              {"lowest_phi_init", low->phi_init},
                              {"largest_consistent_phi_init", largest_consistent},
                              {"compression_time_saved", saved}});
  }
  pool_window_scatter(out, series, o.for_estimate(levels), margin);
  return out;
}

}  // namespace jam::checks
