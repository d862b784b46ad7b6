#pragma once
// <output>/manifest.toml: the campaign's plan as it runs, so that the stages after it (jam
// stats) read its runs without planning the campaign again. Written when a campaign run starts
// and again when it ends, from the plan that run made:
//   campaign_file, campaign (the text it ran), added_samples (the text of added-samples.toml
//   then, "" for none), code_version, and for each run, keyed by its name: order (its place in
//   the plan), n, phi_init, log10_rate, sample, fingerprint_key (the FNV-1a key of its
//   fingerprint, sim_config.hpp: every parameter that changes its numbers), and status,
//   wall_seconds, cpu_seconds, version, detail as its files said when the manifest was written.
// The statuses are a snapshot for people; a reader judges each run from its files again.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "campaign/campaign_dir.hpp"

namespace jam {

/// A run as the manifest records it: enough to find its file and judge it.
struct ManifestRun {
  std::string name;  // <output>/runs/<name>.h5
  std::int64_t n = 0;
  double phi_init = 0, log10_rate = 0;
  std::int64_t sample = 0;
  std::string fingerprint_key;  // FNV-1a 64 (hex) of fingerprint(config)
};

/// Rewrites <output>/manifest.toml from the plan and the run files and records.
void write_manifest(const Campaign& campaign, const std::vector<PlannedRun>& plan);

/// The manifest's runs in plan order when it is current: written with the plan's fields, for
/// the campaign.toml and added-samples.toml the directory holds now. nullopt otherwise (none,
/// older, unreadable, or its plan inputs changed since): the reader plans the campaign.
std::optional<std::vector<ManifestRun>> read_current_manifest(const std::string& directory);

/// run_status (campaign_dir.hpp) of a manifest's run in `directory`, its file judged against
/// the recorded fingerprint key; nullopt when the file stores no fingerprint (schema 1) or
/// another one: only the planned run can judge it, and say which parameters differ.
std::optional<RunStatus> manifest_run_status(const std::string& directory, const ManifestRun& run,
                                             std::string* detail = nullptr);

}  // namespace jam
