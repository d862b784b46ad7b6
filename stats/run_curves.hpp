#pragma once
// The finished runs of a campaign directory as curves against packing fraction, grouped into
// ensembles: one ensemble per (size, phi_init, rate), its members the samples.
// Statistics only read run files; they never run a simulation.
#include <compare>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace jam::stats {

struct RunCurves {
  std::int64_t n = 0;
  double phi_init = 0.0;
  double log10_rate = 0.0;
  std::int64_t sample = 0;
  std::vector<double> phi, pressure, contacts, contacts_no_rattlers;  // last one may be empty
  std::optional<double> jamming_point;  // phi_Ji when the run looked for it (NaN: not found)
};

struct EnsembleKey {
  std::int64_t n = 0;  // 0: sizes pooled
  double phi_init = 0.0;
  double log10_rate = 0.0;
  auto operator<=>(const EnsembleKey&) const = default;
};

using Ensembles = std::map<EnsembleKey, std::vector<RunCurves>>;

struct CampaignData {
  std::string name;
  int dim = 2;
  double phi_step = 0.001;
  // Chained starts (campaign key chain_phi_init): log10 rate -> phi'_init of the chained rates.
  std::map<double, double> chain_phi_init;
  std::vector<RunCurves> runs;
  std::vector<std::string> skipped;  // runs not done (missing, partial, failed, corrupt)
};

/// Every finished run of the campaign stored in directory (see campaign/campaign_dir.hpp).
CampaignData read_campaign_runs(const std::string& directory);

/// Groups runs by (size, phi_init, rate); with pool_sizes all sizes share one ensemble (n = 0)
/// and the samples of every size are its members, numbered n * kPooledSampleStride + sample so
/// that sample k of one size and of another stay two samples (jackknife blocks, covariance).
constexpr std::int64_t kPooledSampleStride = 10'000'000;
Ensembles group_runs(const std::vector<RunCurves>& runs, bool pool_sizes);

}  // namespace jam::stats
