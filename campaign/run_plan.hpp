#pragma once
// The runs of a campaign: one per (size, phi_init, rate, sample), each with its seed, file
// name, simulator configuration and estimated cost.
//
// Seeds derive from (base seed, size, phi_init, sample) only, never from the rate or the
// number of samples: sample k of a size starts from the same configuration at every rate (as
// in the paper), and adding rates, samples or phi_init values never changes an existing run.
#include <cstdint>
#include <string>
#include <vector>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_file.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {

struct PlannedRun {
  std::int64_t n = 0;
  double phi_init = 0.0;
  double log10_rate = 0.0;
  std::int64_t sample = 0;
  std::string name;  // file stem, e.g. n1024_phi0.8000_r-4.50_s003
  SimConfig config;  // config.out = <output>/runs/<name>.h5
  double estimated_particle_steps = 0.0;
  // Chained starts: the run this one continues from ("" for none); it runs first.
  std::string parent;
  // A parent's estimated particle-steps up to the start it leaves (config.write_start_at), for
  // rewriting a lost start without redoing the run (run_chains.hpp).
  double start_particle_steps = 0.0;
};

/// splitmix64 of the tuple, a documented, platform-independent mixing.
std::uint64_t derive_seed(std::uint64_t base_seed, std::int64_t n, double phi_init,
                          std::int64_t sample);

std::string run_name(std::int64_t n, double phi_init, double log10_rate, std::int64_t sample);

/// The simulator configuration of one run (out and start_cache are left empty).
SimConfig run_config(const Campaign& campaign, std::int64_t n, double phi_init, double log10_rate,
                     std::int64_t sample);

/// Every run of the campaign, longest (most particle-steps) first: its samples, and those
/// added to some ensembles in its directory (campaign/added_samples.hpp).
std::vector<PlannedRun> plan_runs(const Campaign& campaign);
/// The same with the added samples given.
std::vector<PlannedRun> plan_runs(const Campaign& campaign, const SampleCounts& added);

/// The campaign whose starts `c` reads (c.chain_starts_from: its stored campaign.toml, its
/// output taken as that directory). Throws CampaignError naming the key.
Campaign starts_campaign(const Campaign& c);

/// Directory holding the run files of a campaign.
std::string runs_directory(const Campaign& campaign);

/// Directory holding the relaxed starts shared by the rates of a sample.
std::string starts_directory(const Campaign& campaign);

/// Directory holding the chained starts (campaign_file.hpp, chain_phi_init).
std::string chain_directory(const Campaign& campaign);

}  // namespace jam

namespace jam {

/// The K-th of N shares of a campaign (K = 1 .. N), for N independent jobs such as a Slurm job
/// array: the runs of each sample (size, phi_init, sample: they share a relaxed start) go to
/// one share, whole samples assigned longest-first to the least loaded share. Deterministic and
/// computed from the whole plan, not from what is pending, so the shares are disjoint and
/// together the whole campaign however far each job got. Indices into plan.
std::vector<std::size_t> shard_of(const std::vector<PlannedRun>& plan, int k, int n);

}  // namespace jam
