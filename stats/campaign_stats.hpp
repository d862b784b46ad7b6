#pragma once
// `jam stats DIR`: everything the statistics stage computes from a campaign directory, and
// the options that steer it. Reads run files only; writes DIR/stats.h5 (reference/schema.md).
#include <optional>
#include <string>
#include <vector>

#include "stats/averages.hpp"
#include "stats/run_curves.hpp"
#include "stats/scaling_fit.hpp"

namespace jam::stats {

struct StatsOptions {
  double z_step = 0.01;                // grid spacing in Z for constant-Z averages
  bool no_rattlers = false;            // constant-Z averages with rattlers removed
  bool pool_sizes = false;             // average the sizes together (after the finite-size check)
  std::optional<double> fit_phi_init;  // ensembles of this phi_init are fitted (default: lowest)
  int order = 5;
  std::optional<double> fixed_phi_j, fixed_q, fixed_inv_znu;
  std::vector<double> half_windows = {0.03, 0.02, 0.01};  // phi windows phi_J0 +- these
  bool fit = true;
};

/// phi_Ji over the samples of an ensemble (runs with jamming_point).
struct JammingStats {
  std::vector<double> samples;  // per run, NaN where the run did not bracket it
  std::vector<std::int64_t> sample_ids;
  SampleMean mean;      // over the runs that found it
  double spread = 0.0;  // standard deviation over samples, Delta phi_J
};

struct EnsembleStats {
  EnsembleKey key;
  GridAverage constant_phi;
  std::optional<GridAverage> constant_z;
  std::optional<JammingStats> jamming;
};

struct ScanRow {
  double rate_max = 0, phi_min = 0, phi_max = 0;
  std::optional<ScalingFitResult> result;
  std::string failure;  // why the fit could not be done
};

struct CampaignStats {
  CampaignData data;
  std::vector<EnsembleStats> ensembles;
  std::optional<ScalingFitResult> fit;  // narrowest window, slowest rate_max with >= 3 rates
  std::string fit_failure;
  ScanRow fit_row;
  std::vector<ScanRow> scan;
  double fit_phi_init = 0.0;
  std::int64_t fit_size = 0;  // 0: pooled
  double wall_time = 0.0;     // seconds spent reading and averaging (provenance for reports)
};

CampaignStats compute_campaign_stats(const std::string& directory, const StatsOptions& options);

/// Writes DIR/stats.h5 atomically.
void write_stats_file(const std::string& path, const CampaignStats& stats,
                      const StatsOptions& options);

/// The summary table for terminals and CI logs.
std::string format_stats_summary(const CampaignStats& stats);

}  // namespace jam::stats
