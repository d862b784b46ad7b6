// Independence of phi_init (the paper's supplement, "Compression Protocol"): Delta p/p between
// runs started at each phi_init and runs started at the lowest one, same size and rate, over
// phi >= phi_min (default phi_J - 0.03, where the paper needs the curves to agree), with the
// statistics of the finite-size check. Memory of the random start fades at slower rates, so the
// verdicts are per rate; each summary says the largest phi_init still consistent with the lowest
// and the share of compression time that starting there saves.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "checks/checks.hpp"
#include "checks/relative_difference.hpp"
#include "sim/model/paper_values.hpp"

namespace jam::checks {
namespace {
double alpha_jamming(const CheckOptions& o, std::size_t comparisons) {
  return o.alpha / static_cast<double>(std::max<std::size_t>(1, comparisons));
}
}  // namespace

std::vector<Verdict> phi_init_check(const StatsData& d, const CheckOptions& o) {
  const double phi_min = o.phi_min.value_or(paper_values(d.dim).phi_j - 0.03);
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
  if (comparisons == 0) return {skipped("phi_init", "all", "the campaign has a single phi_init")};
  const double alpha = o.alpha / static_cast<double>(comparisons);
  std::vector<Verdict> out;
  for (const auto& [key, starts] : by) {
    const auto* low = starts.begin()->second;
    double largest_consistent = low->phi_init;
    bool all_consistent_so_far = true;
    for (auto it = std::next(starts.begin()); it != starts.end(); ++it) {
      const auto* e = it->second;
      Verdict v;
      v.check = "phi_init";
      v.case_name = fmt::format("n{} rate 1e{:g}: phi_init {:g} vs {:g}, phi >= {:.4f}", key.first,
                                key.second, e->phi_init, low->phi_init, phi_min);
      v.statistic_name = "max |Delta p/p| / sigma";
      v.values = {{"n", static_cast<double>(key.first)},
                  {"log10_rate", key.second},
                  {"phi_init", e->phi_init},
                  {"lowest_phi_init", low->phi_init}};
      const Aligned al =
          align(e->phi_grid, e->pressure_at_phi, low->phi_grid, low->pressure_at_phi, phi_min);
      try {
        const RelativeDifference r = compare_run_sets(al.a, al.b, alpha, o.permutations, 3);
        record_test(v, r, alpha);
        std::vector<double> grid;
        for (auto k : r.points) grid.push_back(al.grid[k]);
        v.curves = {{"grid", grid}, {"delta", r.delta}, {"sigma", r.sigma}};
        const double largest_delta =
            *std::max_element(r.delta.begin(), r.delta.end(),
                              [](double x, double y) { return std::abs(x) < std::abs(y); });
        v.reason = fmt::format("permutation p = {:.3g} (alpha {:.3g}); largest Delta p/p {:+.1f}%",
                               r.p_value, alpha, 100 * largest_delta);
        if (v.status == "pass" && all_consistent_so_far) largest_consistent = e->phi_init;
        if (v.status == "fail") all_consistent_so_far = false;
      } catch (const std::invalid_argument& ex) {
        v.status = "skipped";
        v.reason = ex.what();
        all_consistent_so_far = false;
      }
      out.push_back(v);
      // The jamming points themselves, when the runs looked for them.
      if (!e->jamming_points.empty() && !low->jamming_points.empty()) {
        Verdict j;
        j.check = "phi_init";
        j.case_name = fmt::format("n{} rate 1e{:g}: <phi_Ji> at phi_init {:g} vs {:g}", key.first,
                                  key.second, e->phi_init, low->phi_init);
        j.statistic_name = "|<phi_Ji>_a - <phi_Ji>_b| / sigma";
        j.values = v.values;
        try {
          const double a_j = alpha_jamming(o, jamming_comparisons);
          const MeanDifference m =
              compare_means(e->jamming_points, low->jamming_points, a_j, o.permutations, 4);
          record_test(j, m, a_j);
          j.reason = fmt::format(
              "phi_J difference {:+.5f} +- {:.5f}, permutation p = {:.3g} (alpha {:.3g})",
              m.difference, m.sigma, m.p_value, a_j);
        } catch (const std::invalid_argument& ex) {
          j = skipped("phi_init", j.case_name, ex.what());
        }
        out.push_back(j);
      }
    }
    // Compression time from phi0 to phi_stop is ln(phi_stop / phi0) / (D rate).
    const double phi_stop = low->phi_grid.empty() ? 0 : low->phi_grid.back();
    const double saved =
        std::log(largest_consistent / low->phi_init) / std::log(phi_stop / low->phi_init);
    out.back().reason += fmt::format(
        " | n{} rate 1e{:g}: largest phi_init consistent with {:g} is {:g} "
        "(saves {:.0f}% of the compression time)",
        key.first, key.second, low->phi_init, largest_consistent, 100 * saved);
    out.back().values.insert({{"n", static_cast<double>(key.first)},
                              {"log10_rate", key.second},
                              {"lowest_phi_init", low->phi_init},
                              {"largest_consistent_phi_init", largest_consistent},
                              {"compression_time_saved", saved}});
  }
  return out;
}

std::vector<Verdict> run_check(const std::string& name, const StatsData& d, const CheckOptions& o) {
  if (name == "finite_size") return finite_size_check(d, o);
  if (name == "sample_pairs") return sample_pairs_check(d, o);
  if (name == "phi_init") return phi_init_check(d, o);
  if (name == "all") {
    std::vector<Verdict> all;
    for (auto* check : {&finite_size_check, &sample_pairs_check, &phi_init_check}) {
      const auto v = check(d, o);
      all.insert(all.end(), v.begin(), v.end());
    }
    return all;
  }
  throw std::invalid_argument(
      fmt::format("check '{}': unknown (finite_size, sample_pairs, phi_init, all)", name));
}

}  // namespace jam::checks
