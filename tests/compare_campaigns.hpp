#pragma once
// Small campaigns of open runs, imported and averaged as a user's would be (import, `jam
// stats`, stats.h5), for the compare check's tests (test_compare_diagnosis, test_compare_ranges):
// 64 particles from phi 0.80 at rate 1e-4, each run a pressure
//   p = 1e-3 exp(30 (phi - 0.84)) (1 + 1e-3 - exp(-(phi - 0.8) / 0.0015)) exp(eps)
// that builds up over the start's transient and then grows as exp(30 phi), eps an
// Ornstein-Uhlenbeck process along phi (correlation length 0.005), Z rising from 3.5, output
// every 0.001 in phi, with the differences a test plants.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "campaign/external_campaign.hpp"
#include "checks/stats_data.hpp"
#include "open_run_fixture.hpp"
#include "sim/io/open_run.hpp"
#include "stats/campaign_stats.hpp"

namespace jam::test {

struct CompareDesign {
  double shift = 0.0;        // the pressure times 1 + shift for phi > shift_above
  double shift_above = 0.0;  // (0: everywhere)
  double start_shift = 0.0;  // ... and times 1 + start_shift exp(-(phi - 0.80) / 0.004)
  int samples = 8;
  double scatter = 0.05;     // of one run's pressure
  double stop = 0.86;        // the last output packing of every run ...
  double stop_first = NAN;   // ... but of sample 0, when given
  int every = 1;             // every how many of the 0.001-spaced points is written
  bool jamming_point = false;  // each run's phi_Ji drawn near 0.84 (one more draw per run)
  std::string dynamics = "overdamped", contact = "harmonic";
  double quality_factor = 0.0;
};

inline OpenRun compare_run(int sample, const CompareDesign& d, std::mt19937_64& rng) {
  OpenRun r = open_run_of(64, 1e-4, 0.80, sample);
  r.dynamics = d.dynamics;
  r.quality_factor = d.quality_factor;
  r.contact = d.contact;
  std::normal_distribution<double> g(0.0, 1.0);
  const double rho = std::exp(-0.001 / 0.005);
  double eps = d.scatter * g(rng);
  const double stop = sample == 0 && std::isfinite(d.stop_first) ? d.stop_first : d.stop;
  for (int k = 0; 0.80 + 0.001 * k <= stop + 1e-9; ++k) {
    const double phi = 0.80 + 0.001 * k;
    if (k > 0) eps = rho * eps + d.scatter * std::sqrt(1 - rho * rho) * g(rng);
    if (k % d.every != 0) continue;
    const double build_up = 1 + 1e-3 - std::exp(-(phi - 0.80) / 0.0015);
    const double planted = (phi > d.shift_above ? 1 + d.shift : 1.0) *
                           (1 + d.start_shift * std::exp(-(phi - 0.80) / 0.004));
    r.packing_fraction.push_back(phi);
    r.pressure.push_back(1e-3 * std::exp(30 * (phi - 0.84)) * build_up * planted * std::exp(eps));
    r.contacts_per_particle.push_back(3.5 + 15 * (phi - 0.80));
  }
  if (d.jamming_point) r.jamming_packing_fraction = 0.84 + 0.002 * g(rng);
  return r;
}

/// A campaign of d.samples such runs imported into root/name, averaged; its stats.h5 as compare
/// reads it.
inline checks::StatsData compare_campaign(const std::filesystem::path& root,
                                          const std::string& name, const CompareDesign& d,
                                          std::uint64_t seed) {
  namespace fs = std::filesystem;
  const fs::path sources = root / (name + "-sources"), dir = root / name;
  fs::remove_all(sources);
  fs::remove_all(dir);
  fs::create_directories(sources);
  std::mt19937_64 rng(seed);
  std::vector<std::string> files;
  for (int s = 0; s < d.samples; ++s) {
    files.push_back((sources / ("run" + std::to_string(s) + ".h5")).string());
    write_open_run(files.back(), compare_run(s, d, rng));
  }
  import_runs(dir.string(), files, {});
  stats::StatsOptions o;
  o.fit = false;  // one rate: no scaling fit, so REF's range is past the transients to its end
  stats::write_stats_file((dir / "stats.h5").string(), stats::compute_campaign_stats(dir.string(), o),
                          o);
  return checks::read_stats(dir.string());
}

}  // namespace jam::test
