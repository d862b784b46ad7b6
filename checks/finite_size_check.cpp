// Finite size (the paper's supplement, "relE-p" and "relE-p-constZ"): Delta p/p between two
// system sizes against phi and against Z, for every phi_init and rate, pooled over the
// campaign's scaling-fit window (checks/pooled_verdict.hpp), and in the regions below, at and
// above jamming (checks/regions.hpp): four verdicts per comparison when phi_J is known. A
// difference is detected at alpha / (number of verdicts), so the whole check's false-alarm
// rate is alpha; each pass is a two one-sided test at alpha.
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

struct Comparison {
  const EnsembleTables* a;
  const EnsembleTables* b;
  bool at_z;
  std::string label;
};

std::vector<Verdict> compare(const Comparison& c, Levels levels, const StatsData& d,
                             const CheckOptions& o, const JammingReference& jamming) {
  Verdict v;
  v.check = "finite_size";
  v.case_name = c.label;
  // What was compared, as numbers, for the report (checks.json "values", checks.h5 attributes).
  v.values = {{"n_a", static_cast<double>(c.a->n)},
              {"n_b", static_cast<double>(c.b->n)},
              {"phi_init", c.a->phi_init},
              {"log10_rate", c.a->log10_rate},
              {"constant_z", c.at_z ? 1.0 : 0.0}};
  // From where the compression, not the start, sets the pressure in both sets.
  const double from_phi = std::max(c.a->compressed_from_phi, c.b->compressed_from_phi);
  const double from = c.at_z ? std::max(c.a->compressed_from_z, c.b->compressed_from_z) : from_phi;
  v.values["compared_from"] = from;
  PoolRange range =
      c.at_z ? z_range(d, o, *c.a, *c.b, from) : *phi_range(d, o, from, false, nullptr);
  range.pointwise_from = pointwise_start(c.at_z, *c.a, *c.b, from_phi);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const std::vector<PoolRange> regions =
      region_ranges(names, jamming, c.at_z, *c.a, *c.b, from, range.pointwise_from);
  const Aligned al = c.at_z ? align(c.a->z_grid, c.a->pressure_at_z, c.b->z_grid,
                                    c.b->pressure_at_z, from, HUGE_VAL)
                            : align(c.a->phi_grid, c.a->pressure_at_phi, c.b->phi_grid,
                                    c.b->pressure_at_phi, from, HUGE_VAL);
  if (al.grid.empty() || al.a.size() < 2 || al.b.size() < 2) {
    v.status = "inconclusive";
    v.region = "pooled";
    v.reason =
        fmt::format("no common grid points in {} (or fewer than 2 samples per set)", range.why);
    return {v};
  }
  return judge_by_region(v, al, range, names, regions, levels, o.margin("finite_size"),
                         o.permutations);
}

}  // namespace

std::vector<Verdict> finite_size_check(const StatsData& d, const CheckOptions& o) {
  std::vector<Comparison> comparisons;
  if (o.set_a && o.set_b) {
    const EnsembleTables *a = nullptr, *b = nullptr;
    for (const auto& e : d.ensembles) {
      if (!a && o.set_a->matches(e))
        a = &e;
      else if (!b && o.set_b->matches(e))
        b = &e;
    }
    if (!a || !b) {
      return {inconclusive("finite_size", "named run sets",
                           "a named run set matches no ensemble of stats.h5")};
    }
    for (bool z : {false, true}) {
      comparisons.push_back(
          {a, b, z,
           fmt::format("{} vs {}, constant {}", case_label(*a), case_label(*b), z ? "Z" : "phi")});
    }
  } else {
    if (d.pooled) {
      return {inconclusive("finite_size", "all",
                           "stats.h5 pooled the sizes; run `jam stats` without --pool-sizes")};
    }
    // Smallest against largest size at every (phi_init, rate).
    std::map<std::pair<double, double>, std::map<std::int64_t, const EnsembleTables*>> by;
    for (const auto& e : d.ensembles) by[{e.phi_init, e.log10_rate}][e.n] = &e;
    for (const auto& [key, sizes] : by) {
      if (sizes.size() < 2) continue;
      const auto* a = sizes.begin()->second;
      const auto* b = sizes.rbegin()->second;
      for (bool z : {false, true}) {
        comparisons.push_back({a, b, z,
                               fmt::format("n{} vs n{}, phi_init {:g}, rate 1e{:g}, constant {}",
                                           a->n, b->n, key.first, key.second, z ? "Z" : "phi")});
      }
    }
    if (comparisons.empty()) {
      return {inconclusive("finite_size", "all", "the campaign has a single system size")};
    }
  }
  std::vector<Verdict> out;
  // Detection shared over every verdict: comparisons x (pooled + regions).
  const JammingReference jamming = jamming_reference(d, o.phi_j);
  const Levels levels{o.alpha / static_cast<double>(comparisons.size() *
                                                    verdicts_per_comparison(jamming, o.regions)),
                      o.alpha};
  // The samples estimate pools each series' scatter over its rates (window_scatter.hpp); a
  // sample costs in proportion to N at one rate.
  std::vector<ScatterSeries> series;
  std::map<std::tuple<std::int64_t, std::int64_t, double, bool, std::string>, int> series_of;
  for (const auto& c : comparisons) {
    for (auto& v : compare(c, levels, d, o, jamming)) {
      out.push_back(std::move(v));
      const auto key = std::tuple{c.a->n, c.b->n, c.a->phi_init, c.at_z, out.back().region};
      const int id = series_of.emplace(key, static_cast<int>(series_of.size())).first->second;
      series.push_back({out.size() - 1, id, c.a->log10_rate, static_cast<double>(c.a->n),
                        static_cast<double>(c.b->n), fmt::format("N = {}", c.a->n),
                        fmt::format("N = {}", c.b->n)});
    }
  }
  pool_window_scatter(out, series, o.for_estimate(levels), o.margin("finite_size"));
  return out;
}

RunSetSelector RunSetSelector::parse(const std::string& text) {
  RunSetSelector s;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string field = text.substr(start, end - start);
    const std::size_t eq = field.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(
          fmt::format("run set '{}': field '{}' is not key=value", text, field));
    const std::string key = field.substr(0, eq), value = field.substr(eq + 1);
    try {
      if (key == "n")
        s.n = std::stoll(value);
      else if (key == "phi_init")
        s.phi_init = std::stod(value);
      else if (key == "rate")
        s.log10_rate = std::stod(value);
      else
        throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument(
          fmt::format("run set '{}': field '{}' (keys: n, phi_init, rate as log10)", text, field));
    }
    start = end + 1;
  }
  return s;
}

bool RunSetSelector::matches(const EnsembleTables& e) const {
  return (!n || *n == e.n) && (!phi_init || std::abs(*phi_init - e.phi_init) < 1e-9) &&
         (!log10_rate || std::abs(*log10_rate - e.log10_rate) < 1e-9);
}

}  // namespace jam::checks
