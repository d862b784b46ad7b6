#pragma once
// `jam bench throughput`: particle-steps per second of jam's overdamped Euler step near
// jamming (2D phi = 0.84, 3D phi = 0.64) for N = n_min, 4 n_min, ... n_max, on one core and on
// both cores, beside LAMMPS (bench_compress.in) on the same configuration and the same number
// of cores, measured in one run so that the ratios share the machine's load.
//
// Per (D, N): a random configuration at phi, spatially sorted, 150 Euler steps (dt 0.05, no
// compression) to remove the worst overlaps of the random start; then the timed steps, Euler
// at dt 0.01 compressing at rate 1e-4. The same configuration is written as a LAMMPS data file
// and LAMMPS runs its inertial model at Q = 0.1, dt = 0.8 x its stability bound 4 Q^2/D (its
// best setting in the accuracy benchmark), rate 1e-4, timed by its own "Loop time".
// Modes: "1 core" (one run), "2 cores: campaign" (two independent runs at once: jam two
// threads, LAMMPS two processes; the sum of both), "2 cores: one run" (LAMMPS on 2 MPI ranks;
// jam's single run uses one thread, so its one-core number is shown).
#include <cstdint>
#include <string>
#include <vector>

namespace jam::bench {

struct ThroughputOptions {
  std::vector<int> dims{2, 3};
  std::int64_t n_min = 1024, n_max = 1048576;
  double seconds = 1.0;  // target duration of each jam measurement
  int repeats = 3;       // every measurement, jam and LAMMPS in turn; medians reported
  bool lammps = true;
  bool two_cores = true;
  std::string out_dir = "reports/benchmarks";
  std::string reference_dir;  // reference/lammps
  std::string command;        // the command line, recorded in the report
};

struct ThroughputRow {
  int dim = 2;
  std::int64_t n = 0;
  std::string mode;
  int cores = 1;
  long steps = 0;       // timed steps per run (jam)
  double jam = 0.0;     // particle-steps per second, all runs of the mode together
  double lammps = 0.0;  // the same for LAMMPS; 0 when not run
  long lammps_steps = 0;
  double jam_bytes = 0.0;        // bytes per particle (arrays of one run)
  double lammps_bytes = 0.0;     // LAMMPS's per-rank memory x ranks / N
  double builds_per_step = 0.0;  // neighbor-list builds per timed step (jam)
};

std::vector<ThroughputRow> run_throughput(const ThroughputOptions& o);

/// Writes throughput.csv, throughput.md and throughput.png into o.out_dir.
void write_throughput_report(const ThroughputOptions& o, const std::vector<ThroughputRow>& rows);

}  // namespace jam::bench
