#pragma once
// Samples added to some ensembles of a campaign beyond its `samples`, by `jam campaign run
// --until-decided` (design/until_decided.hpp): <output>/added-samples.toml, jam's own file in the
// campaign directory. Every planner of the directory reads it (run_plan.cpp), so the runner,
// `jam stats`, `jam campaign status` and the shards all see one plan.
//
//   [[ensemble]]
//   n = 256
//   phi_init = 0.4
//   log10_rate = -8.0
//   samples = 20        # samples of this ensemble in all (>= the campaign's samples)
//
// A chained rate's sample continues from the same sample of the next faster rate, so that
// rate runs at least as many samples (samples_per_ensemble).
#include <compare>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "campaign/campaign_file.hpp"

namespace jam {

struct EnsembleId {
  std::int64_t n = 0;
  double phi_init = 0, log10_rate = 0;
  auto operator<=>(const EnsembleId&) const = default;
};

/// Samples per ensemble, for the ensembles that have more than the campaign's `samples`.
using SampleCounts = std::map<EnsembleId, std::int64_t>;

/// The campaign's own spelling of an ensemble given by values read back from a file (sizes
/// exactly, phi_init and rate to 1e-9); nullopt when it is not one of the campaign's.
std::optional<EnsembleId> campaign_ensemble(const Campaign& c, const EnsembleId& e);

/// <output>/added-samples.toml.
std::string added_samples_path(const Campaign& c);

/// The added samples of c's directory (empty when the file is absent). Every entry must name
/// an ensemble of c (its values taken from c's lists) with samples >= c.samples; the file
/// must keep the campaign within kMaxCampaignRuns. Throws CampaignError naming the field.
SampleCounts read_added_samples(const Campaign& c);

/// Writes <output>/added-samples.toml atomically (removes it when counts is empty).
void write_added_samples(const Campaign& c, const SampleCounts& counts);

/// The samples of every ensemble of c: c.samples, the added ones, and for a chained campaign
/// each rate at least as many as the chained rate that continues from it.
SampleCounts samples_per_ensemble(const Campaign& c, const SampleCounts& added);

}  // namespace jam
