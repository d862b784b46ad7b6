// Numerical convergence as a verdict: a campaign's pressures against the same runs redone at a
// stricter integrator setting (`jam campaign converge`: the compression tolerance a tenth, the
// error in the largest component, the same starts; for chained rates the campaign's own stored
// parents), ensemble by ensemble, over the same samples only. Delta p/p is relative to the
// converged runs, pooled over the campaign's fit window and in the regions below, at and above
// jamming, at a margin well below the physics margins (1%: a tenth of the 10% a size or start
// effect is judged at). The two share their starts, so they are judged sample by sample (a
// paired test, judge_paired): the samples' scatter, which is the physics', cancels, and what
// is left is the integrator's error and the chaos that parts single trajectories. pass: the
// integrator's error is excluded beyond the margin there; fail: the campaign's own numbers are off
// by more than it, and what they say about the physics is in doubt; inconclusive: the re-runs are
// too few to tell (single trajectories part chaotically below 0.1%, so the comparison is of
// ensembles).
#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/regression_check.hpp"

namespace jam::checks {
namespace {

/// The two sets' rows over the grid values both have in [lo, hi], row i of each the same
/// sample (the campaign's samples that were redone, in the converged set's order).
struct Paired {
  std::vector<double> grid;
  std::vector<std::vector<double>> run, converged;
};

Paired paired(const EnsembleTables& e, const EnsembleTables& c, double lo, double hi) {
  Paired out;
  std::map<std::int64_t, std::size_t> row_of;
  for (std::size_t i = 0; i < e.sample_ids.size() && i < e.pressure_at_phi.size(); ++i)
    row_of[e.sample_ids[i]] = i;
  std::vector<std::size_t> rows_e, rows_c;
  for (std::size_t j = 0; j < c.sample_ids.size() && j < c.pressure_at_phi.size(); ++j) {
    const auto it = row_of.find(c.sample_ids[j]);
    if (it != row_of.end()) rows_e.push_back(it->second), rows_c.push_back(j);
  }
  std::vector<std::vector<double>> a, b;
  for (auto i : rows_e) a.push_back(e.pressure_at_phi[i]);
  for (auto j : rows_c) b.push_back(c.pressure_at_phi[j]);
  if (a.empty()) return out;
  const Aligned al = align(e.phi_grid, a, c.phi_grid, b, lo, hi);
  // Points finite and positive in every row of both.
  for (std::size_t k = 0; k < al.grid.size(); ++k) {
    bool ok = true;
    for (const auto* set : {&al.a, &al.b})
      for (const auto& r : *set) ok = ok && std::isfinite(r[k]) && r[k] > 0;
    if (!ok) continue;
    out.grid.push_back(al.grid[k]);
  }
  auto keep = [&](const std::vector<std::vector<double>>& rows) {
    std::vector<std::vector<double>> t(rows.size());
    for (std::size_t k = 0, m = 0; k < al.grid.size() && m < out.grid.size(); ++k) {
      if (al.grid[k] != out.grid[m]) continue;
      for (std::size_t i = 0; i < rows.size(); ++i) t[i].push_back(rows[i][k]);
      ++m;
    }
    return t;
  };
  out.run = keep(al.a);
  out.converged = keep(al.b);
  return out;
}

/// The same runs at two settings judged sample by sample, since they share their starts: per
/// sample i the weighted mean over the range of d_ik = (p_run - p_converged)_ik / <p_converged>_k,
/// the weights w_k ~ 1 / var_i(d_ik) (where the two settings part least), and the samples'
/// mean D and its error judged with Student t at n - 1 degrees of freedom: pass when |D| +
/// t(pass) sigma <= M, fail when |D| - t(detect) sigma > M (margin.hpp), detected when |D| /
/// sigma > t(detect / 2).
void judge_paired(Verdict& v, const Paired& p, const PoolRange& range, Levels levels,
                  double margin) {
  const std::size_t n = p.run.size(), m = p.grid.size();
  if (n < 2 || m < 2) {
    v.status = "inconclusive";
    v.margin = margin;
    v.reason = fmt::format("fewer than 2 samples or 2 common points in {} [{:.4g}, {:.4g}] ({})",
                           range.variable, range.min, range.max, range.why);
    return;
  }
  std::vector<std::vector<double>> d(n, std::vector<double>(m));
  std::vector<double> weight(m);
  for (std::size_t k = 0; k < m; ++k) {
    double mean_c = 0;
    for (std::size_t i = 0; i < n; ++i) mean_c += p.converged[i][k] / static_cast<double>(n);
    double mean = 0, var = 0;
    for (std::size_t i = 0; i < n; ++i) {
      d[i][k] = (p.run[i][k] - p.converged[i][k]) / mean_c;
      mean += d[i][k] / static_cast<double>(n);
    }
    for (std::size_t i = 0; i < n; ++i) var += (d[i][k] - mean) * (d[i][k] - mean);
    weight[k] = 1.0 / std::max(var / static_cast<double>(n - 1), 1e-24);
  }
  const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
  std::vector<double> per_sample(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < m; ++k) per_sample[i] += weight[k] / total * d[i][k];
  const double mean =
      std::accumulate(per_sample.begin(), per_sample.end(), 0.0) / static_cast<double>(n);
  double var = 0;
  for (double x : per_sample) var += (x - mean) * (x - mean);
  const double sigma = std::sqrt(var / static_cast<double>(n - 1) / static_cast<double>(n));
  const double dof = static_cast<double>(n - 1);
  const double t_pass = gsl_cdf_tdist_Qinv(levels.pass, dof),
               t_beyond = gsl_cdf_tdist_Qinv(levels.detect, dof),
               t_detect = gsl_cdf_tdist_Qinv(levels.detect / 2, dof);
  v.statistic = sigma > 0 ? std::abs(mean) / sigma : HUGE_VAL;
  v.threshold = t_detect;
  v.detectable = t_detect * sigma;
  v.estimate = mean;
  decide(v, v.statistic > t_detect, std::abs(mean) + t_pass * sigma,
         std::abs(mean) - t_beyond * sigma, margin);
  v.reason += fmt::format(
      " (mean over {} samples of each one's weighted mean (p_run - p_converged) / p_converged: "
      "{} +- {}, Student t at {:.0f} degrees of freedom, alpha {:.3g}; over phi in [{:.4g}, "
      "{:.4g}], {})",
      n, effect_text(v, mean, true), effect_text(v, sigma), dof, levels.detect, p.grid.front(),
      p.grid.back(), range.why);
  v.values["difference"] = mean;
  v.values["range_min"] = p.grid.front();
  v.values["range_max"] = p.grid.back();
  v.values["samples_a"] = v.values["samples_b"] = static_cast<double>(n);
  std::vector<double> mean_d(m, 0.0), sigma_d(m, 0.0);
  for (std::size_t k = 0; k < m; ++k) {
    for (std::size_t i = 0; i < n; ++i) mean_d[k] += d[i][k] / static_cast<double>(n);
    for (std::size_t i = 0; i < n; ++i) sigma_d[k] += (d[i][k] - mean_d[k]) * (d[i][k] - mean_d[k]);
    sigma_d[k] = std::sqrt(sigma_d[k] / static_cast<double>(n - 1) / static_cast<double>(n));
  }
  v.curves = {{"grid", p.grid}, {"delta", mean_d}, {"sigma", sigma_d}};
}

/// The rows of `e` whose sample is in `ids`, in e's order.
EnsembleTables only_samples(const EnsembleTables& e, const std::set<std::int64_t>& ids) {
  EnsembleTables out = e;
  out.pressure_at_phi.clear();
  out.sample_ids.clear();
  for (std::size_t i = 0; i < e.sample_ids.size() && i < e.pressure_at_phi.size(); ++i) {
    if (!ids.contains(e.sample_ids[i])) continue;
    out.sample_ids.push_back(e.sample_ids[i]);
    out.pressure_at_phi.push_back(e.pressure_at_phi[i]);
  }
  return out;
}

}  // namespace

std::vector<Verdict> convergence_check(const StatsData& campaign, const StatsData& converged,
                                       const CheckOptions& o, const RegressionOptions&) {
  std::map<EnsembleKey, const EnsembleTables*> strict;
  for (const auto& e : converged.ensembles) strict[ensemble_key(e)] = &e;
  std::vector<std::pair<EnsembleTables, const EnsembleTables*>> pairs;
  for (const auto& e : campaign.ensembles) {
    const auto it = strict.find(ensemble_key(e));
    if (it == strict.end()) continue;
    const std::set<std::int64_t> ids(it->second->sample_ids.begin(), it->second->sample_ids.end());
    pairs.emplace_back(only_samples(e, ids), it->second);
  }
  if (pairs.empty()) {
    return {inconclusive("convergence", "all",
                         "no ensemble of the campaign (size, phi_init, rate) was redone in the "
                         "--against directory: `jam campaign converge` writes the campaign "
                         "file that redoes them")};
  }
  const JammingReference jamming = jamming_reference(campaign, o.phi_j);
  const std::vector<Region> names = regions_around(jamming, o.regions);
  const Levels levels{
      o.alpha / static_cast<double>(pairs.size() * verdicts_per_comparison(jamming, o.regions)),
      o.alpha};
  const double margin = o.margin("convergence");
  std::vector<Verdict> out;
  for (const auto& [e, c] : pairs) {
    Verdict v;
    v.check = "convergence";
    v.case_name = fmt::format("{}: as run vs converged", case_label(e));
    v.statistic_name = "|weighted mean (p_run - p_converged) / p_converged|";
    v.values = {{"n", static_cast<double>(e.n)},
                {"phi_init", e.phi_init},
                {"log10_rate", e.log10_rate},
                {"samples_compared", static_cast<double>(e.sample_ids.size())}};
    if (e.sample_ids.size() != c->sample_ids.size()) {  // a sample redone the campaign lacks
      out.push_back(inconclusive(
          "convergence", v.case_name,
          fmt::format("the converged runs are samples the campaign does not hold ({} of {} "
                      "found): the comparison needs the same starts",
                      e.sample_ids.size(), c->sample_ids.size())));
      continue;
    }
    const double compressed = std::max(e.compressed_from_phi, c->compressed_from_phi);
    const PoolRange range = *phi_range(campaign, o, compressed, false, nullptr);
    std::vector<PoolRange> ranges = {range};
    for (auto& r : region_ranges(names, jamming, false, e, *c, compressed, -HUGE_VAL))
      ranges.push_back(std::move(r));
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      Verdict x = v;
      x.region = i == 0 ? "pooled" : names[i - 1].name;
      if (i > 0) x.case_name += ", " + names[i - 1].case_words();
      judge_paired(x, paired(e, *c, ranges[i].min, ranges[i].max), ranges[i], levels, margin);
      if (i == 0) say_if_whole(x, ranges[0], ranges.size() > 1);
      out.push_back(std::move(x));
    }
  }
  return out;
}

}  // namespace jam::checks
