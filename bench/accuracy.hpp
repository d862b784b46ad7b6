#pragma once
// `jam bench accuracy`: run time against the error of the pressure, for every integrator and
// time step, jam and LAMMPS, on fixed relaxed starts compressed through jamming.
//
// Headline (process_runs.hpp): jam as users run it. Each start is written as a LAMMPS data file
// and `jam sim --read-lammps-data ... --relax 0 --phi-step 0.0005` (the campaigns' output grid)
// runs as its own process, at its defaults and with steps landed on every output point; the
// time is the whole process, spawn to exit. LAMMPS's time there is its whole process too. With
// `unrelaxed` (default), also from the random starts as generated (no relaxation), against a
// reference from those starts, with and without the transient tolerance.
//
// Per dimension and seed: N random particles at phi_start (default 2D 0.80, 3D 0.60), relaxed at
// zero rate with Euler (dt 0.01) to an energy per particle <= 1e-10 or for relax_time (default 500
// t0; the start only has to be the same for every method, but an unrelaxed start carries a
// residual stress into the pressure: start lower and relax longer to probe slow rates). Per rate:
// every method compresses that start to the last of three packings, phi_J - 0.01, phi_J and phi_J +
// 0.015 (phi_J the paper's), landing on each exactly (the step before it is shortened), where the
// virial pressure is read. LAMMPS (bench_compress.in, inertial, same start, zero velocities)
// prints its pressure every ~0.05 t0, interpolated (quadratic in time) to the packings. Its
// line for step m has the forces of the box before the step's deformation and the volume after
// it: engine "lammps" reads it as printed (time m dt, what a user gets), "lammps-shifted" (the
// same runs) at time (m-1) dt with the volume of that time, which happens to cancel most of
// the splitting error of the deformation; "LAMMPS best" takes the better of the two.
// Reference: Heun at dt_ref, dt_ref/2, dt_ref/4 per seed; Richardson's p_R = p(h/4) +
// (p(h/4) - p(h/2))/3, and the ratio of successive differences (4 for order 2) shows it
// converged. Error of a method at a packing: |mean over seeds of p/p_R - 1| (single chaotic
// trajectories decorrelate below ~0.1%, means over seeds do not), with its standard error;
// a method's error is the largest over the three packings. Wall time of the other tables:
// median over seeds of the compression alone (jam: its stepping loop; LAMMPS: its "Loop time").
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace jam::bench {

struct AccuracyOptions {
  std::vector<int> dims{2, 3};
  std::int64_t n = 4096;
  std::vector<double> rates{1e-3, 1e-4};
  int seeds = 4;
  std::vector<double> euler_dt{0.005, 0.01, 0.02, 0.05, 0.1};
  std::vector<double> heun_dt{0.01, 0.02, 0.05, 0.1};
  // Local error tolerances (d_s) of the adaptive Chebyshev integrator (its first step 0.1).
  std::vector<double> chebyshev_tolerance{1e-2, 3e-3, 1e-3, 1e-4};
  std::vector<double> verlet_quality_factors{0.1, 0.03};
  std::vector<double> verlet_fraction{0.8};
  std::vector<double> lammps_fraction{0.8};
  double reference_dt = 0.01;
  // The headline: jam as a user runs it (whole processes of `jam sim` at the campaigns' output
  // grid, phi_step 0.0005) from the relaxed starts and, when set, from unrelaxed ones.
  bool unrelaxed = true;
  // Each whole process (jam's and LAMMPS's) is run this many times and timed by the median:
  // a 40 ms process on a shared machine moves by 10-20% between single runs.
  int process_repeats = 3;
  double phi_start_2d = 0.80, phi_start_3d = 0.60;  // packing of the starts
  double relax_time = 500.0;  // relaxation of the starts stops here (or at 1e-10 per particle)
  double start_packing(int dim) const { return dim == 2 ? phi_start_2d : phi_start_3d; }
  bool lammps = true;
  int jobs = 1;
  std::string out_dir = "reports/benchmarks";
  std::string reference_dir;  // reference/lammps
  std::string command;
};

/// One method (engine, integrator, Q, dt) at one dimension and rate, over the seeds.
struct Method {
  int dim = 2;
  double rate = 0.0;
  std::string engine;             // jam | jam-process | lammps | lammps-shifted
  std::string start = "relaxed";  // relaxed | unrelaxed (jam-process and its references)
  std::vector<std::string> args;  // jam-process: options of `jam sim` beyond the defaults
  std::string integrator;         // euler | heun | verlet | reference-h | reference-h/2 | ...
  double quality_factor = 0.0;    // inertial only
  double dt = 0.0;
  double tolerance = 0.0;                       // chebyshev only (dt is then its first step)
  std::vector<double> wall;                     // per seed, seconds
  std::vector<double> process_wall;             // per seed: the whole process (jam-process, lammps)
  std::vector<std::array<double, 3>> pressure;  // per seed, at the three packings
  // Filled by the analysis:
  double wall_median = 0.0, process_wall_median = 0.0;
  std::array<double, 3> error{}, error_se{};
  double max_error = 0.0, max_error_se = 0.0;
  bool is_reference = false;
};

/// Per dimension and rate: the packings and the reference's convergence.
struct Reference {
  int dim = 2;
  double rate = 0.0;
  std::string start = "relaxed";
  std::array<double, 3> phi{};
  std::array<double, 3> p{};          // mean over seeds of p_R
  std::array<double, 3> ratio{};      // mean |p(h)-p(h/2)| / mean |p(h/2)-p(h/4)|
  std::array<double, 3> remaining{};  // mean |p_R - p(h/4)| / p_R
};

struct AccuracyResult {
  std::vector<Method> methods;
  std::vector<Reference> references;
};

AccuracyResult run_accuracy(const AccuracyOptions& o);

/// Writes accuracy.csv, accuracy.md (with the time to 1% and 0.1% error) and accuracy.png.
void write_accuracy_report(const AccuracyOptions& o, const AccuracyResult& r);

/// The packings of the benchmark: phi_J - 0.01, phi_J, phi_J + 0.015 (phi_J the paper's,
/// rounded to the output grid of 0.0005).
std::array<double, 3> accuracy_packings(int dim);

}  // namespace jam::bench
