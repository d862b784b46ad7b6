#include "checks/lammps_runner.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>

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

}  // namespace jam::checks
