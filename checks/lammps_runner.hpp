#pragma once
// Running the Debian `lmp` on reference/lammps/compress_inertial.in for the LAMMPS checks.
#include <cstdint>
#include <filesystem>
#include <string>

namespace jam::checks {

bool lmp_available();

/// The first line of a LAMMPS log: "LAMMPS (29 Sep 2021 - Update 2)".
std::string lammps_version(const std::filesystem::path& log);

/// Runs the template in dir on dir/<data> (inputs copied next to it, so the log names files
/// rather than this machine's paths), writing dir/<log> and dir/<end>; throws if lmp fails.
void run_lammps(const std::filesystem::path& dir, const std::filesystem::path& reference, int dim,
                double rate, double dt, long steps, long every, const std::string& data,
                const std::string& log, const std::string& end,
                const std::string& contact = "harmonic");

/// A start for a comparison: N = 256 random particles at phi, relaxed at zero rate (with the
/// given dynamics) to the energy target, written as a LAMMPS data file with the masses of Q.
struct StartSpec {
  int dim = 2;
  double phi = 0.8, quality_factor = 0.1, dt = 0.01;
  std::string dynamics = "overdamped";
  std::string relax_energy = "1e-12";
  std::uint64_t seed = 1;
};
void write_relaxed_start(const StartSpec& spec, const std::filesystem::path& data);

}  // namespace jam::checks
