#include "stats/campaign_stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "sim/model/paper_values.hpp"

namespace jam::stats {
namespace {}  // namespace

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
    e.constant_phi = average_at_constant_phi(runs, s.data.phi_step);
    try {
      e.constant_z = average_at_constant_z(runs, o.z_step, o.no_rattlers);
    } catch (const std::invalid_argument&) {
      if (o.no_rattlers) throw;
    }
    if (std::all_of(runs.begin(), runs.end(),
                    [](const RunCurves& r) { return r.jamming_point.has_value(); })) {
      JammingStats j;
      SampleAccumulator acc;
      for (const auto& r : runs) {
        j.samples.push_back(*r.jamming_point);
        j.sample_ids.push_back(r.sample);
        if (std::isfinite(*r.jamming_point)) acc.add(*r.jamming_point);
      }
      j.mean = acc.finalize();
      j.spread =
          j.mean.samples > 1 ? j.mean.error * std::sqrt(static_cast<double>(j.mean.samples)) : NAN;
      e.jamming = std::move(j);
    }
    s.ensembles.push_back(std::move(e));
  }
  if (!o.fit) return s;

  // Which ensembles enter the fit: one phi_init, the pooled or the largest size.
  std::set<double> phi_inits;
  std::set<std::int64_t> sizes;
  for (const auto& e : s.ensembles) {
    phi_inits.insert(e.key.phi_init);
    sizes.insert(e.key.n);
  }
  s.fit_phi_init = o.fit_phi_init.value_or(*phi_inits.begin());
  s.fit_size = *sizes.rbegin();
  std::vector<FitEnsemble> fit_data;
  for (const auto& e : s.ensembles) {
    if (std::abs(e.key.phi_init - s.fit_phi_init) > 1e-9 || e.key.n != s.fit_size) continue;
    FitEnsemble f;
    f.rate = std::pow(10.0, e.key.log10_rate);
    f.phi = e.constant_phi.grid;
    f.pressure = e.constant_phi.table("pressure");
    for (auto id : e.constant_phi.sample_ids) f.sample_ids.push_back(id);
    fit_data.push_back(std::move(f));
  }
  if (fit_data.empty()) {
    s.fit_failure = fmt::format("no ensembles with phi_init {:g}", s.fit_phi_init);
    return s;
  }
  std::sort(fit_data.begin(), fit_data.end(),
            [](const FitEnsemble& a, const FitEnsemble& b) { return a.rate > b.rate; });

  const PaperValues paper = paper_values(s.data.dim);  // starts and window centres
  ScalingFitOptions base;
  base.order = o.order;
  base.fixed_phi_j = o.fixed_phi_j;
  base.fixed_q = o.fixed_q;
  base.fixed_inv_znu = o.fixed_inv_znu;
  base.start_phi_j = paper.phi_j;
  base.start_q = paper.q();
  base.start_inv_znu = paper.inv_znu();
  const double centre = o.fixed_phi_j.value_or(paper.phi_j);
  // rate_max from the fastest rate down to the third slowest, so every fit sees >= 3 rates
  // (or all of them when there are fewer).
  std::vector<double> rate_max;
  for (std::size_t k = 0; k < fit_data.size(); ++k) {
    if (fit_data.size() - k >= 3 || k == 0) rate_max.push_back(fit_data[k].rate);
  }
  for (double half : o.half_windows) {
    for (double rm : rate_max) {
      ScanRow row;
      row.rate_max = rm;
      row.phi_min = centre - half;
      row.phi_max = centre + half;
      ScalingFitOptions f = base;
      f.phi_min = row.phi_min;
      f.phi_max = row.phi_max;
      f.rate_max = rm;
      try {
        row.result = fit_scaling(fit_data, f);
      } catch (const FitError& e) {
        row.failure = e.what();
      }
      s.scan.push_back(row);
    }
  }
  // The representative fit, as the paper: narrowest window, smallest rate_max.
  s.fit_row = s.scan.back();
  s.fit = s.fit_row.result;
  s.fit_failure = s.fit_row.failure;
  return s;
}

}  // namespace jam::stats
