#include "app/bench_command.hpp"

#include <fmt/format.h>

#include <sstream>
#include <stdexcept>

#include "sim/io/output_path.hpp"

namespace jam {
namespace {

std::vector<int> parse_dims(const std::string& text) {
  std::vector<int> dims;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (item != "2" && item != "3")
      throw std::runtime_error(fmt::format("--dims {}: a list of 2 and 3, e.g. 2,3", text));
    dims.push_back(item == "2" ? 2 : 3);
  }
  if (dims.empty()) throw std::runtime_error(fmt::format("--dims {}: empty", text));
  return dims;
}

}  // namespace

void add_bench_command(CLI::App& app, BenchArgs& a) {
  CLI::App* b = app.add_subcommand("bench", "Benchmarks against LAMMPS: throughput, accuracy");
  b->require_subcommand(1);
  CLI::App* t = b->add_subcommand(
      "throughput",
      "Particle-steps/s near jamming for N = n-min ... n-max, 1 and 2 cores, vs LAMMPS");
  t->option_defaults()->always_capture_default();
  t->add_option("--dims", a.dims, "Dimensions, comma-separated");
  t->add_option("--n-min", a.throughput.n_min, "Smallest N (then x4)");
  t->add_option("--n-max", a.throughput.n_max, "Largest N");
  t->add_option("--seconds", a.throughput.seconds, "Target duration of each jam measurement");
  t->add_option("--repeats", a.throughput.repeats, "Repeats of every measurement (medians)");
  t->add_flag("!--no-lammps", a.throughput.lammps, "Without LAMMPS");
  t->add_flag("!--one-core", a.throughput.two_cores, "Only the one-core measurements");
  t->add_option("--out-dir", a.throughput.out_dir, "Where the report files go");
  t->add_option("--reference-dir", a.throughput.reference_dir, "LAMMPS inputs");

  CLI::App* c = b->add_subcommand(
      "accuracy", "Pressure error against wall time for every integrator and dt, vs LAMMPS");
  c->option_defaults()->always_capture_default();
  auto& o = a.accuracy;
  c->add_option("--dims", a.dims, "Dimensions, comma-separated");
  c->add_option("--n", o.n, "Particles");
  c->add_option("--rates", o.rates, "Compression rates");
  c->add_option("--seeds", o.seeds, "Starting configurations (errors are means over them)");
  c->add_option("--euler-dt", o.euler_dt, "Time steps of overdamped Euler");
  c->add_option("--heun-dt", o.heun_dt, "Time steps of overdamped Heun");
  c->add_option("--chebyshev-tolerance", o.chebyshev_tolerance,
                "Local error tolerances of the adaptive Chebyshev integrator (its first step 0.1)");
  c->add_option("--verlet-q", o.verlet_quality_factors,
                "Quality factors of the inertial runs (jam and LAMMPS)");
  c->add_option("--verlet-dt-fraction", o.verlet_fraction,
                "Inertial time steps as fractions of the stability bound 4 Q^2 / D");
  c->add_option("--lammps-dt-fraction", o.lammps_fraction,
                "LAMMPS time steps as fractions of the same bound");
  c->add_option("--reference-dt", o.reference_dt,
                "Heun reference: dt, dt/2, dt/4 (Richardson from the last two)");
  c->add_option("--phi-start-2d", o.phi_start_2d, "Packing of the 2D starts");
  c->add_option("--phi-start-3d", o.phi_start_3d, "Packing of the 3D starts");
  c->add_option("--relax-time", o.relax_time,
                "Relaxation of the starts stops after this time (t0) or at 1e-10 per particle");
  c->add_flag("!--no-lammps", o.lammps, "Without LAMMPS");
  c->add_flag("!--no-unrelaxed", o.unrelaxed,
              "Whole processes from the relaxed starts only (not also from unrelaxed ones)");
  c->add_option("--process-repeats", o.process_repeats,
                "Runs of each whole process (jam sim, lmp), timed by their median");
  c->add_option("--jobs", o.jobs, "Runs at once (timings are cleanest with 1)");
  c->add_option("--out-dir", o.out_dir, "Where the report files go");
  c->add_option("--reference-dir", o.reference_dir, "LAMMPS inputs");
}

int run_bench_command(const CLI::App& app, BenchArgs& a, int argc, char** argv) {
  std::string command = "jam";
  for (int k = 1; k < argc; ++k) command += std::string(" ") + argv[k];
  const CLI::App* b = app.get_subcommand("bench");
  // Refused before hours of benchmarking, not after.
  check_output_directory(
      "out-dir", b->got_subcommand("throughput") ? a.throughput.out_dir : a.accuracy.out_dir);
  if (b->got_subcommand("throughput")) {
    a.throughput.dims = parse_dims(a.dims);
    a.throughput.command = command;
    const auto rows = bench::run_throughput(a.throughput);
    bench::write_throughput_report(a.throughput, rows);
    fmt::print("wrote {}/throughput.md, .csv, .png\n", a.throughput.out_dir);
    return 0;
  }
  a.accuracy.dims = parse_dims(a.dims);
  a.accuracy.command = command;
  const auto result = bench::run_accuracy(a.accuracy);
  bench::write_accuracy_report(a.accuracy, result);
  fmt::print("wrote {}/accuracy.md, .csv, .png\n", a.accuracy.out_dir);
  return 0;
}

}  // namespace jam
