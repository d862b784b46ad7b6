#include "checks/lammps_runner.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "sim/io/process.hpp"
#include "sim/run/compression_run.hpp"

namespace jam::checks {
namespace fs = std::filesystem;

bool lmp_available() {
  return !find_program("lmp").empty();
}

std::string lammps_version(const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);
  return line;
}

void run_lammps(const fs::path& dir, const fs::path& reference, int dim, double rate, double dt,
                long steps, long every, const std::string& data, const std::string& log,
                const std::string& end) {
  for (const char* f : {"compress_inertial.in", "harmonic_contact.table"}) {
    fs::copy_file(reference / f, dir / f, fs::copy_options::overwrite_existing);
  }
  // Species of the paper: gamma_s = k_d V_s = 2/D, V_b/V_s = 1.4^D, d_sb = 1.2, d_bb = 1.4.
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  const std::vector<std::string> argv = {"lmp",
                                         "-log",
                                         log,
                                         "-screen",
                                         "none",
                                         "-in",
                                         "compress_inertial.in",
                                         "-var",
                                         "data",
                                         data,
                                         "-var",
                                         "table",
                                         "harmonic_contact.table",
                                         "-var",
                                         "out",
                                         end,
                                         "-var",
                                         "dim",
                                         std::to_string(dim),
                                         "-var",
                                         "rate",
                                         g(rate),
                                         "-var",
                                         "dt",
                                         g(dt),
                                         "-var",
                                         "steps",
                                         std::to_string(steps),
                                         "-var",
                                         "every",
                                         std::to_string(every),
                                         "-var",
                                         "skin",
                                         "0.3",
                                         "-var",
                                         "gamma_s",
                                         g(2.0 / dim),
                                         "-var",
                                         "drag_ratio",
                                         g(std::pow(1.4, dim)),
                                         "-var",
                                         "d_sb",
                                         "1.2",
                                         "-var",
                                         "d_bb",
                                         "1.4"};
  ProcessOptions where;
  where.working_directory = dir;
  where.stdout_file = "/dev/null";
  if (const int status = run_program(argv, where); status != 0) {
    throw std::runtime_error(
        fmt::format("lmp failed (exit status {}); see {}", status, (dir / log).string()));
  }
}

void write_relaxed_start(const StartSpec& spec, const fs::path& data) {
  SimConfig a;
  a.dim = spec.dim;
  a.n = 256;
  a.phi_init = spec.phi;
  a.phi_stop = spec.phi * 1.001;  // the start is written before any compression step
  a.compression_rate = 1e-3;
  a.dynamics = spec.dynamics;
  a.q = spec.q;
  a.dt = spec.dt;
  a.relax_energy = spec.relax_energy;
  a.seed = spec.seed;
  a.quiet = true;
  a.checkpoint_interval = 0;
  a.out = (data.parent_path() / "start_run.h5").string();
  a.write_lammps_data = data.string();
  run_compression(a);
}

}  // namespace jam::checks
