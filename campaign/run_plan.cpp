#include "campaign/run_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "campaign/added_samples.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/observables/jamming_point.hpp"

namespace jam {
namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Relaxation of a random start at zero rate, measured at phi = 0.6 in 2D: about 365 t0 to
// reach 1e-12 per particle. A rough, conservative allowance for the cost estimate.
constexpr double kRelaxTimeEstimate = 400.0;

// FIRE steps of one jamming-point minimization at N = 1024 (see jamming_search_particle_steps).
constexpr double kFireStepsAt1024 = 2.5e4;

/// The jamming point's search (observables/jamming_point.hpp): a bisection over the saved
/// output points and then along the path to kJammingResolution, each probe a FIRE minimization
/// to a largest force of 1e-10 near phi_J. Measured 2026-11-26 (2D, rate 1e-4, 0.80 -> 0.86,
/// phi_step 0.0005, 15 minimizations each): about 0.6 s per minimization at N = 1024, 41 s at
/// N = 16384, so FIRE steps per minimization grow as ~ N^0.5 from ~2.5e4 at N = 1024; the
/// search cost 10x (N = 1024) to 40x (N = 16384) the compression itself there.
double jamming_search_particle_steps(const SimConfig& s, double phi_from) {
  if (!s.jamming_point) return 0.0;
  const double from = std::max(phi_from, s.jamming_search_from);
  const double points = std::max(2.0, (s.phi_stop - from) / s.phi_step);
  const double minimizations =
      std::ceil(std::log2(points)) + std::ceil(std::log2(s.phi_step / kJammingResolution));
  const double n = static_cast<double>(s.n);
  return minimizations * kFireStepsAt1024 * std::sqrt(n / 1024.0) * n;
}

/// Particle-steps of a run compressing from `phi_from` (relaxing first if its config says so,
/// searching its jamming point after if it asks for one).
double estimated_particle_steps(const SimConfig& s, double phi_from) {
  const std::string integrator = s.resolved_integrator();
  const double n = static_cast<double>(s.n);
  const double relax_time = s.relax ? kRelaxTimeEstimate : 0.0;
  return n * (compression_force_evaluations(integrator, s.dim, s.dt, s.compression_rate,
                                            s.resolved_tolerance(), s.rms_error_norm(), n, phi_from,
                                            s.phi_stop) +
              relaxation_evaluations_per_time(integrator, s.dt) * relax_time) +
         jamming_search_particle_steps(s, phi_from);
}

/// Chained starts: each rate with a chain_phi_init continues from the next faster rate of the
/// same sample (fastest first, so that a parent's fingerprint is final before its child's
/// identity is taken from it). `runs` in plan order before sorting, rates innermost but one.
void link_chains(const Campaign& c, std::vector<PlannedRun>& runs) {
  if (c.chain_phi_init.empty() || !c.chain_starts_from.empty()) return;
  std::map<std::tuple<std::int64_t, double, double, std::int64_t>, std::size_t> at;
  for (std::size_t k = 0; k < runs.size(); ++k)
    at[{runs[k].n, runs[k].phi_init, runs[k].log10_rate, runs[k].sample}] = k;
  const std::vector<std::size_t> order = rates_fastest_first(c);
  const std::string chain_dir = chain_directory(c);
  std::set<std::tuple<std::int64_t, double, std::int64_t>> samples;
  for (const auto& r : runs) samples.insert({r.n, r.phi_init, r.sample});
  for (const auto& [n, phi, sample] : samples) {
    for (std::size_t i = 1; i < order.size(); ++i) {
      const double phi_start = c.chain_phi_init[order[i]];
      if (phi_start == 0.0) continue;
      PlannedRun& child = runs[at.at({n, phi, c.log10_rates[order[i]], sample})];
      PlannedRun& parent = runs[at.at({n, phi, c.log10_rates[order[i - 1]], sample})];
      SimConfig to_start = parent.config;
      to_start.phi_stop = phi_start;
      to_start.jamming_point = false;
      const double parent_from =
          i > 1 && c.chain_phi_init[order[i - 1]] > 0.0 ? c.chain_phi_init[order[i - 1]] : phi;
      parent.start_particle_steps = estimated_particle_steps(to_start, parent_from);
      const std::string path =
          (std::filesystem::path(chain_dir) / (child.name + ".start.h5")).string();
      parent.config.write_start = path;
      parent.config.write_start_at = phi_start;
      child.parent = parent.name;
      child.config.relax = false;
      child.config.start_cache.clear();
      child.config.read_start = path;
      child.config.start_identity = chain_start_identity(fingerprint(parent.config), phi_start);
      child.estimated_particle_steps = estimated_particle_steps(child.config, phi_start);
    }
  }
}

/// Runs redone from another campaign's starts (campaign_file.hpp, chain_starts_from): each
/// chained rate reads the start its namesake there reads, from that campaign's chain
/// directory, with the identity its parent there gives it. Planning needs only the path: when
/// that campaign is not at hand (a plan of the cost) or has no such run, the identity stays
/// empty, and `jam campaign run` refuses it (restore_starts.hpp) before any work.
void take_starts_from(const Campaign& c, std::vector<PlannedRun>& runs) {
  if (c.chain_starts_from.empty()) return;
  std::map<double, double> chained;  // log10 rate -> the packing its start is taken at
  for (std::size_t k = 0; k < c.chain_phi_init.size(); ++k)
    if (c.chain_phi_init[k] > 0.0) chained[c.log10_rates[k]] = c.chain_phi_init[k];
  const std::filesystem::path from(c.chain_starts_from);
  std::map<std::string, SimConfig> theirs;
  if (std::filesystem::exists(from / "campaign.toml")) {
    const Campaign other = starts_campaign(c);
    // Its starts must be its own: a chain of campaigns reading each other's (or a campaign
    // reading its own) would never end.
    if (!other.chain_starts_from.empty()) {
      throw CampaignError(fmt::format(
          "{}: chain_starts_from {}: that campaign reads its own starts from {}; name the "
          "campaign that chains them",
          c.source_path, c.chain_starts_from, other.chain_starts_from));
    }
    for (auto& r : plan_runs(other)) theirs.emplace(r.name, std::move(r.config));
  }
  for (auto& r : runs) {
    const auto at = chained.find(r.log10_rate);
    if (at == chained.end()) continue;  // a relaxed start: the same seed, relaxed here
    r.config.relax = false;
    r.config.start_cache.clear();
    r.config.read_start = (from / "chain" / (r.name + ".start.h5")).string();
    r.config.start_identity.clear();
    if (const auto it = theirs.find(r.name);
        it != theirs.end() && it->second.read_start == r.config.read_start)
      r.config.start_identity = it->second.start_identity;
    r.estimated_particle_steps = estimated_particle_steps(r.config, at->second);
  }
}

}  // namespace

Campaign starts_campaign(const Campaign& c) {
  const std::filesystem::path dir(c.chain_starts_from);
  Campaign from;
  try {
    from = read_campaign((dir / "campaign.toml").string());
  } catch (const std::exception& e) {
    throw CampaignError(
        fmt::format("{}: chain_starts_from {}: {}", c.source_path, c.chain_starts_from, e.what()));
  }
  from.output = dir.string();  // its paths as seen from here
  return from;
}

std::uint64_t derive_seed(std::uint64_t base_seed, std::int64_t n, double phi_init,
                          std::int64_t sample) {
  const auto phi_key = static_cast<std::uint64_t>(std::llround(phi_init * 1e6));
  std::uint64_t h = splitmix64(base_seed);
  h = splitmix64(h ^ static_cast<std::uint64_t>(n));
  h = splitmix64(h ^ phi_key);
  h = splitmix64(h ^ static_cast<std::uint64_t>(sample));
  return h >> 1;  // below 2^63, so it is stored exactly as an int64 attribute
}

std::string run_name(std::int64_t n, double phi_init, double log10_rate, std::int64_t sample) {
  return fmt::format("n{}_phi{:.4f}_r{:+.2f}_s{:03d}", n, phi_init, log10_rate, sample);
}

std::string runs_directory(const Campaign& campaign) {
  return (std::filesystem::path(campaign.output) / "runs").string();
}

SimConfig run_config(const Campaign& c, std::int64_t n, double phi_init, double log10_rate,
                     std::int64_t sample) {
  SimConfig s = c.run;  // every campaign key; the rest are SimConfig's defaults
  s.n = n;
  s.phi_init = phi_init;
  s.compression_rate = std::pow(10.0, log10_rate);
  s.seed = derive_seed(c.base_seed, n, phi_init, sample);
  s.campaign = c.name;
  s.sample = sample;
  return s;
}

std::string starts_directory(const Campaign& campaign) {
  return (std::filesystem::path(campaign.output) / "starts").string();
}

std::string chain_directory(const Campaign& campaign) {
  return (std::filesystem::path(campaign.output) / "chain").string();
}

std::vector<PlannedRun> plan_runs(const Campaign& c) {
  return plan_runs(c, read_added_samples(c));
}

std::vector<PlannedRun> plan_runs(const Campaign& c, const SampleCounts& added) {
  std::vector<PlannedRun> runs;
  std::set<std::string> names;
  const std::string dir = runs_directory(c);
  // The campaign's samples, and those `--until-decided` added to some ensembles.
  const SampleCounts samples = samples_per_ensemble(c, added);
  for (auto n : c.sizes) {
    for (double phi : c.phi_init) {
      for (double lr : c.log10_rates) {
        const std::int64_t count = samples.at({n, phi, lr});
        for (std::int64_t k = c.first_sample; k < c.first_sample + count; ++k) {
          PlannedRun r;
          r.n = n;
          r.phi_init = phi;
          r.log10_rate = lr;
          r.sample = k;
          r.name = run_name(n, phi, lr, k);
          if (!names.insert(r.name).second) {
            throw CampaignError(
                fmt::format("{}: phi_init or log10_rates values closer than the run names resolve "
                            "(4 and 2 decimals): {}",
                            c.source_path, r.name));
          }
          r.config = run_config(c, n, phi, lr, k);
          SimConfig& s = r.config;
          s.out = (std::filesystem::path(dir) / (r.name + ".h5")).string();
          if (s.relax && s.relax_energy != "auto") {
            // One relaxed start per sample and relaxing integrator (rates of one sample can
            // default to different integrators; Heun's starts keep their old names).
            const std::string integrator = s.resolved_integrator();
            s.start_cache = (std::filesystem::path(starts_directory(c)) /
                             fmt::format("n{}_phi{:.4f}_s{:03d}{}.h5", n, phi, k,
                                         integrator == "heun" ? std::string() : "_" + integrator))
                                .string();
          }
          r.estimated_particle_steps = estimated_particle_steps(s, phi);
          runs.push_back(std::move(r));
        }
      }
    }
  }
  link_chains(c, runs);
  take_starts_from(c, runs);
  std::stable_sort(runs.begin(), runs.end(), [](const PlannedRun& a, const PlannedRun& b) {
    return a.estimated_particle_steps > b.estimated_particle_steps;
  });
  return runs;
}

}  // namespace jam

namespace jam {

std::vector<std::size_t> shard_of(const std::vector<PlannedRun>& plan, int k, int n) {
  // Samples and their cost, in a fixed order (cost, then key).
  std::map<std::tuple<std::int64_t, double, std::int64_t>, double> cost;
  for (const auto& run : plan)
    cost[{run.n, run.phi_init, run.sample}] += run.estimated_particle_steps;
  std::vector<std::pair<double, std::tuple<std::int64_t, double, std::int64_t>>> samples;
  for (const auto& [key, c] : cost) samples.emplace_back(c, key);
  std::stable_sort(samples.begin(), samples.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<double> load(static_cast<std::size_t>(n), 0.0);
  std::set<std::tuple<std::int64_t, double, std::int64_t>> mine;
  for (const auto& [c, key] : samples) {
    const auto least = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    load[static_cast<std::size_t>(least)] += c;
    if (least == k - 1) mine.insert(key);
  }
  std::vector<std::size_t> share;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    if (mine.count({plan[i].n, plan[i].phi_init, plan[i].sample})) share.push_back(i);
  }
  return share;
}

}  // namespace jam
