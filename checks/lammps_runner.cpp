#include "checks/lammps_runner.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "sim/run/compression_run.hpp"

namespace jam::checks {
namespace fs = std::filesystem;

bool lmp_available() {
  return std::system("command -v lmp > /dev/null 2>&1") == 0;
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
  const std::string cmd = fmt::format(
      "cd {} && lmp -log {} -screen none -in compress_inertial.in -var data {} -var table "
      "harmonic_contact.table -var out {} -var dim {} -var rate {:.17g} -var dt {:.17g} -var steps "
      "{} "
      "-var every {} -var skin 0.3 -var gamma_s {:.17g} -var drag_ratio {:.17g} -var d_sb 1.2 "
      "-var d_bb 1.4",
      dir.string(), log, data, end, dim, rate, dt, steps, every, 2.0 / dim, std::pow(1.4, dim));
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("lmp failed: " + cmd);
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
