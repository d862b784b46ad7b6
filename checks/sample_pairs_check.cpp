// Sample pairs (the paper's panels "#16 -- #32"): Delta p/p between sample i of one size and
// sample i of the other, and whether its spread matches the sample-to-sample fluctuations
// measured within each size. Statistic R = mean over points of <Delta_pair^2> / (v_a + v_b),
// v the relative sample variance within a size: about 1 when the pairs differ only by
// sample-to-sample noise, above 1 when the sizes differ systematically, below when samples
// are not independent. Its two-sided acceptance band comes from a bootstrap under the null
// that keeps each size's own scatter (pair_ratio_null).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/permutation.hpp"
#include "checks/pooled_verdict.hpp"

namespace jam::checks {
namespace {

double pair_ratio(const std::vector<const std::vector<double>*>& a,
                  const std::vector<const std::vector<double>*>& b) {
  const std::size_t m = a.front()->size(), pairs = std::min(a.size(), b.size());
  auto relative_variance = [&](const std::vector<const std::vector<double>*>& set, std::size_t k) {
    double mean = 0.0, ss = 0.0;
    for (const auto* r : set) mean += (*r)[k] / static_cast<double>(set.size());
    for (const auto* r : set) ss += ((*r)[k] - mean) * ((*r)[k] - mean);
    return ss / static_cast<double>(set.size() - 1) / (mean * mean);
  };
  double sum = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    double d2 = 0.0;
    for (std::size_t i = 0; i < pairs; ++i) {
      const double pa = (*a[i])[k], pb = (*b[i])[k];
      const double d = 2.0 * (pa - pb) / (pa + pb);
      d2 += d * d / static_cast<double>(pairs);
    }
    sum += d2 / (relative_variance(a, k) + relative_variance(b, k));
  }
  return sum / static_cast<double>(m);
}

/// R's distribution when the sizes do not differ systematically, each keeping its own scatter
/// (a bootstrap under the null, Efron and Tibshirani ch. 16): every run of a set rescaled
/// pointwise to the mean of both sets, then each set resampled with replacement on its own,
/// pair i the i-th draw of each. Relabelling runs between the sizes instead (the former null)
/// gave both the pooled scatter: with hundreds of samples it detected N = 128 scattering more
/// than N = 1024, which is no difference of the pressures. Sorted; seeded, so deterministic.
std::vector<double> pair_ratio_null(const std::vector<const std::vector<double>*>& a,
                                    const std::vector<const std::vector<double>*>& b, int draws) {
  const std::size_t m = a.front()->size();
  auto centred = [m](const std::vector<const std::vector<double>*>& set,
                     const std::vector<double>& target) {
    std::vector<double> mean(m, 0.0);
    for (const auto* r : set)
      for (std::size_t k = 0; k < m; ++k) mean[k] += (*r)[k] / static_cast<double>(set.size());
    std::vector<std::vector<double>> out;
    for (const auto* r : set) {
      std::vector<double> x(m);
      for (std::size_t k = 0; k < m; ++k) x[k] = (*r)[k] * target[k] / mean[k];
      out.push_back(std::move(x));
    }
    return out;
  };
  std::vector<double> both(m, 0.0);
  for (const auto* set : {&a, &b})
    for (const auto* r : *set)
      for (std::size_t k = 0; k < m; ++k)
        both[k] += (*r)[k] / static_cast<double>(a.size() + b.size());
  const auto ca = centred(a, both), cb = centred(b, both);
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<std::size_t> pick_a(0, ca.size() - 1), pick_b(0, cb.size() - 1);
  std::vector<double> null;
  std::vector<const std::vector<double>*> pa(a.size()), pb(b.size());
  for (int d = 0; d < draws; ++d) {
    for (auto& r : pa) r = &ca[pick_a(rng)];
    for (auto& r : pb) r = &cb[pick_b(rng)];
    null.push_back(pair_ratio(pa, pb));
  }
  std::sort(null.begin(), null.end());
  return null;
}

/// The verdict of sample pairs over one range (al cut to it already); alpha: the detection
/// level of this verdict.
Verdict judge_pairs(Verdict v, const Aligned& al, const PoolRange& range, double alpha,
                    const CheckOptions& o) {
  // Points where every sample has a positive pressure.
  std::vector<std::size_t> keep;
  for (std::size_t k = 0; k < al.grid.size(); ++k) {
    bool ok = true;
    for (const auto& r : al.a) ok = ok && r[k] > 0 && std::isfinite(r[k]);
    for (const auto& r : al.b) ok = ok && r[k] > 0 && std::isfinite(r[k]);
    if (ok) keep.push_back(k);
  }
  // The samples and the range judged (the range asked, where no point lies in it), for the
  // tables (verdict_table.cpp).
  v.values["samples_a"] = static_cast<double>(al.a.size());
  v.values["samples_b"] = static_cast<double>(al.b.size());
  v.range_variable = range.variable;
  const double range_min = keep.empty() ? range.min : al.grid[keep.front()],
               range_max = keep.empty() ? range.max : al.grid[keep.back()];
  if (std::isfinite(range_min)) v.values["range_min"] = range_min;
  if (std::isfinite(range_max)) v.values["range_max"] = range_max;
  if (keep.empty() || al.a.size() < 3 || al.b.size() < 3) {
    v.status = "inconclusive";
    v.reason =
        fmt::format("fewer than 3 samples per size or no common grid points: in {}", range.why);
    return v;
  }
  std::vector<std::vector<double>> rows;
  for (const auto* set : {&al.a, &al.b})
    for (const auto& r : *set) {
      std::vector<double> x;
      for (auto k : keep) x.push_back(r[k]);
      rows.push_back(std::move(x));
    }
  std::vector<const std::vector<double>*> a, b;
  for (std::size_t i = 0; i < rows.size(); ++i) (i < al.a.size() ? a : b).push_back(&rows[i]);
  v.statistic = pair_ratio(a, b);
  const std::vector<double> null =
      pair_ratio_null(a, b, permutations_for(alpha / 2, o.permutations));
  const auto quantile = [&](double q) {
    return null[std::min(null.size() - 1,
                         static_cast<std::size_t>(q * static_cast<double>(null.size())))];
  };
  const double lo = quantile(alpha / 2), hi = quantile(1 - alpha / 2);
  const double lo_pass = quantile(o.alpha);
  v.threshold = hi;
  // A uniform systematic difference delta adds delta^2 / (v_a + v_b) to R: the smallest one
  // that reaches the threshold from R = 1.
  double v_sum = 0.0;
  for (std::size_t k = 0; k < keep.size(); ++k) {
    double ma = 0, sa = 0, mb = 0, sb = 0;
    for (const auto* r : a) ma += (*r)[k] / static_cast<double>(a.size());
    for (const auto* r : a)
      sa += ((*r)[k] - ma) * ((*r)[k] - ma) / static_cast<double>(a.size() - 1);
    for (const auto* r : b) mb += (*r)[k] / static_cast<double>(b.size());
    for (const auto* r : b)
      sb += ((*r)[k] - mb) * ((*r)[k] - mb) / static_cast<double>(b.size() - 1);
    v_sum += sa / (ma * ma) + sb / (mb * mb);
  }
  const double v_mean = v_sum / static_cast<double>(keep.size());
  v.detectable = std::sqrt(std::max(0.0, hi - 1.0) * v_mean);
  // The effects the data allow: R = 1 + delta^2 / v_mean + noise, and noise above lo is
  // allowed, so delta^2 <= (R - lo) v_mean.
  const double allowed = std::sqrt(std::max(0.0, v.statistic - lo_pass) * v_mean);
  const double margin = o.margin("sample_pairs");
  // ... and the effects it excludes from below: noise above hi is not allowed, so
  // delta^2 > (R - hi) v_mean.
  const double surely = std::sqrt(std::max(0.0, v.statistic - hi) * v_mean);
  decide(v, v.statistic > hi, allowed, surely, margin);
  if (v.statistic < lo) {
    // Pairs more alike than independent samples: the samples of the two sizes are not
    // independent (shared seeds or starts), whatever the margin says.
    v.status = "fail";
    v.reason = "pairs more alike than independent samples (R below its band)";
    v.rule =
        fmt::format("R below its band ({:.3g} < {:.3g}), whatever the margin", v.statistic, lo);
  }
  v.reason += fmt::format(
      " (R = {:.3g}, band [{:.3g}, {:.3g}] of {} bootstrap draws under the null, alpha {:.3g}; "
      "over phi in [{:.4g}, "
      "{:.4g}], {})",
      v.statistic, lo, hi, null.size(), alpha, al.grid[keep.front()], al.grid[keep.back()],
      range.why);
  if (v.status == "inconclusive") {
    // The band's half-width shrinks as 1/sqrt(samples); R - 1 stays.
    const double room = margin * margin / v_mean - (v.statistic - 1.0);
    const double n = static_cast<double>(std::min(a.size(), b.size()));
    if (room > 0 && 1.0 - lo_pass > 0) {
      v.samples_needed = std::ceil(n * std::pow((1.0 - lo_pass) / room, 2));
      v.reason += fmt::format("; about {:.0f} samples per set would decide it (estimate)",
                              v.samples_needed);
    }
  }
  // Delta p/p of each pair (sample i of one size against sample i of the other).
  std::vector<double> grid;
  for (auto k : keep) grid.push_back(al.grid[k]);
  v.curves.emplace_back("grid", grid);
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    std::vector<double> d;
    for (std::size_t k = 0; k < keep.size(); ++k)
      d.push_back(2 * ((*a[i])[k] - (*b[i])[k]) / ((*a[i])[k] + (*b[i])[k]));
    v.curves.emplace_back("pair_" + std::to_string(i), d);
  }
  return v;
}

}  // namespace

std::vector<Verdict> sample_pairs_check(const StatsData& d, const CheckOptions& o) {
  if (d.pooled) {
    return {inconclusive("sample_pairs", "all",
                         "stats.h5 pooled the sizes; run `jam stats` without --pool-sizes")};
  }
  std::map<std::pair<double, double>, std::map<std::int64_t, const EnsembleTables*>> by;
  for (const auto& e : d.ensembles) by[{e.phi_init, e.log10_rate}][e.n] = &e;
  std::size_t comparisons = 0;
  for (const auto& [key, sizes] : by) comparisons += sizes.size() >= 2;
  if (comparisons == 0)
    return {inconclusive("sample_pairs", "all", "the campaign has a single system size")};
  // Detection (R beyond its band on either side) at alpha shared over the comparisons; the
  // allowed effect from R's lower quantile at alpha itself (one-sided, as every pass).
  // ... and over the regions around phi_J beside the pooled range (checks/regions.hpp).
  const JammingReference jamming = jamming_reference(d, o.phi_j);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const double alpha =
      o.alpha / static_cast<double>(comparisons * verdicts_per_comparison(jamming, o.regions));
  std::vector<Verdict> out;
  for (const auto& [key, sizes] : by) {
    if (sizes.size() < 2) continue;
    const auto* ea = sizes.begin()->second;
    const auto* eb = sizes.rbegin()->second;
    Verdict v;
    v.check = "sample_pairs";
    v.case_name = fmt::format("n{} #i vs n{} #i, phi_init {:g}, rate 1e{:g}", ea->n, eb->n,
                              key.first, key.second);
    v.statistic_name = "<Delta_pair^2> / (v_a + v_b)";
    v.values = {{"n_a", static_cast<double>(ea->n)},
                {"n_b", static_cast<double>(eb->n)},
                {"phi_init", key.first},
                {"log10_rate", key.second}};
    // Over the range the pressure checks pool over (the scaling fit's window), where the
    // fitted data are.
    const PoolRange range = *phi_range(
        d, o, std::max(ea->compressed_from_phi, eb->compressed_from_phi), false, nullptr);
    const double compressed = std::max(ea->compressed_from_phi, eb->compressed_from_phi);
    const Aligned al = align(ea->phi_grid, ea->pressure_at_phi, eb->phi_grid, eb->pressure_at_phi,
                             compressed, HUGE_VAL);
    std::vector<PoolRange> ranges = {range};
    for (auto& r : region_ranges(names, jamming, false, *ea, *eb, compressed, -HUGE_VAL))
      ranges.push_back(std::move(r));
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      Verdict x = v;
      x.region = i == 0 ? "pooled" : names[i - 1].name;
      if (i > 0) x.case_name += ", " + names[i - 1].case_words();
      out.push_back(judge_pairs(x, cut(al, ranges[i].min, ranges[i].max), ranges[i], alpha, o));
      if (i == 0) say_if_whole(out.back(), ranges[0], ranges.size() > 1);
    }
  }
  return out;
}

}  // namespace jam::checks
