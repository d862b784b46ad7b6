#include "stats/campaign_stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "stats/fit_scan.hpp"
#include "stats/papers_protocol.hpp"

namespace jam::stats {
namespace {

FitEnsemble fit_ensemble(const EnsembleStats& e, const GridAverage& a,
                         const std::vector<double>& phi) {
  FitEnsemble f;
  f.rate = std::pow(10.0, e.key.log10_rate);
  f.phi = phi;
  f.pressure = a.table("pressure");
  for (auto id : a.sample_ids) f.sample_ids.push_back(id);
  return f;
}

std::vector<double> means_of(const GridAverage& a, const std::string& name) {
  std::vector<double> out;
  for (const auto& m : a.mean(name)) out.push_back(m.mean);
  return out;
}

/// Why the design has no scaling fit: its rates, named.
std::string fewer_rates_words(const std::set<double>& rates, double phi_init, std::int64_t n) {
  std::string listed;
  for (auto it = rates.rbegin(); it != rates.rend(); ++it)
    listed += fmt::format("{}1e{:g}", listed.empty() ? "" : ", ", std::log10(*it));
  return fmt::format(
      "none attempted: fewer than {} rates (the fitted ensembles, phi_init {:g} and N "
      "{}, have {}{}); a scaling fit needs at least {} (with 2, phi_J and q trade off)",
      kFitRatesMin, phi_init, n ? std::to_string(n) : "pooled", rates.size(),
      listed.empty() ? "" : ": " + listed, kFitRatesMin);
}

}  // namespace

CampaignStats compute_campaign_stats(const std::string& directory, const StatsOptions& o) {
  CampaignStats s;
  s.data = read_campaign_runs(directory);
  if (s.data.runs.empty()) {
    throw std::runtime_error(fmt::format("{}: no finished runs to average", directory));
  }
  const Ensembles groups = group_runs(s.data.runs, o.pool_sizes);
  for (const auto& [key, runs] : groups) {
    EnsembleStats e;
    e.key = key;
    if (const auto it = s.data.chain_phi_init.find(key.log10_rate);
        it != s.data.chain_phi_init.end())
      e.chain_phi_init = it->second;
    e.constant_phi = average_at_constant_phi(runs, s.data.phi_step);
    try {
      e.constant_z = average_at_constant_z(runs, o.z_step, o.no_rattlers);
    } catch (const std::invalid_argument&) {
      if (o.no_rattlers) throw;
    }
    e.coverage =
        run_coverage(runs, s.data.phi_step, o.z_step, o.no_rattlers, e.constant_phi, e.constant_z);
    if (std::all_of(runs.begin(), runs.end(),
                    [](const RunCurves& r) { return r.jamming_point.has_value(); })) {
      std::vector<double> points;
      std::vector<std::int64_t> ids;
      for (const auto& r : runs) points.push_back(*r.jamming_point), ids.push_back(r.sample);
      e.jamming = jamming_stats(std::move(points), std::move(ids));
    }
    s.ensembles.push_back(std::move(e));
  }
  s.runs_averaged = static_cast<std::int64_t>(s.data.runs.size());
  s.runs_skipped = static_cast<std::int64_t>(s.data.skipped.size());
  if (o.fit) fit_campaign(s, o);
  return s;
}

JammingStats jamming_stats(std::vector<double> samples, std::vector<std::int64_t> sample_ids) {
  JammingStats j;
  SampleAccumulator acc;
  for (double x : samples)
    if (std::isfinite(x)) acc.add(x);
  j.samples = std::move(samples);
  j.sample_ids = std::move(sample_ids);
  j.mean = acc.finalize();
  j.spread =
      j.mean.samples > 1 ? j.mean.error * std::sqrt(static_cast<double>(j.mean.samples)) : NAN;
  return j;
}

void fit_campaign(CampaignStats& s, const StatsOptions& o) {
  // Which ensembles enter the fit: one phi_init, the pooled or the largest size.
  std::set<double> phi_inits;
  std::set<std::int64_t> sizes;
  for (const auto& e : s.ensembles) {
    phi_inits.insert(e.key.phi_init);
    sizes.insert(e.key.n);
  }
  s.fit_phi_init = o.fit_phi_init.value_or(*phi_inits.begin());
  s.fit_size = *sizes.rbegin();
  std::vector<FitEnsemble> at_phi, at_z;
  for (const auto& e : s.ensembles) {
    if (std::abs(e.key.phi_init - s.fit_phi_init) > 1e-9 || e.key.n != s.fit_size) continue;
    at_phi.push_back(fit_ensemble(e, e.constant_phi, e.constant_phi.grid));
    if (e.constant_z) {
      at_z.push_back(fit_ensemble(e, *e.constant_z, means_of(*e.constant_z, "packing_fraction")));
    }
  }
  // The design decides before any fit: with fewer than 3 rates phi_J and q trade off, and the
  // fitter refuses every row (stats/scaling_fit.cpp), so none is attempted, none is written to
  // stats.h5, and nothing downstream (families, the paper's protocol, the report's figures)
  // sees a fit.
  std::set<double> rates;
  for (const auto& f : at_phi) rates.insert(f.rate);
  if (rates.size() < kFitRatesMin) {
    s.fit.failure = s.fit_z.failure = fewer_rates_words(rates, s.fit_phi_init, s.fit_size);
    return;
  }
  // The verdicts declared to the fit, those it consults (fit_verdicts.hpp): recorded.
  std::vector<EnsembleKey> keys;
  for (const auto& e : s.ensembles) keys.push_back(e.key);
  s.fit_selection = fit_selection(keys, s.fit_phi_init, s.fit_size);
  s.fit_verdicts = consulted(o.verdicts, s.fit_selection);
  StatsOptions used = o;
  used.verdicts = s.fit_verdicts;
  s.clearance = read_clearance(used.verdicts, s.fit_size, s.fit_phi_init, *phi_inits.begin());
  s.fit = scan_fits(at_phi, used, s.clearance, "phi");
  if (!at_z.empty()) s.fit_z = scan_fits(at_z, used, s.clearance, "Z");
  fit_families(s, used);
  s.papers_protocol = fit_papers_protocol(s, used);
}

void fit_families(CampaignStats& s, const StatsOptions& o) {
  const ScalingFitResult* representative = s.fit.representative();
  if (!representative) return;
  const ScanRow& row = s.fit.rows[*s.fit.chosen];
  const ScalingFitOptions fo = fit_options(o, o.order, row.half_window, row.rate_max);
  std::set<std::pair<std::int64_t, double>> families;
  for (const auto& e : s.ensembles) families.insert({e.key.n, e.key.phi_init});
  for (const auto& [n, phi_init] : families) {
    if (n == 0) continue;  // pooled sizes
    FamilyFit f{n, phi_init, std::nullopt, ""};
    std::vector<FitEnsemble> data;
    for (const auto& e : s.ensembles)
      if (e.key.n == n && std::abs(e.key.phi_init - phi_init) <= 1e-9)
        data.push_back(fit_ensemble(e, e.constant_phi, e.constant_phi.grid));
    try {
      f.result = fit_scaling(data, fo);
    } catch (const FitError& err) {
      f.failure = err.what();
    }
    s.families.push_back(std::move(f));
  }
}

}  // namespace jam::stats
