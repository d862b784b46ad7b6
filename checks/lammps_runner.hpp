#pragma once
// Running the Debian `lmp` on reference/lammps/compress_inertial.in for the LAMMPS checks.
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
                const std::string& log, const std::string& end);

}  // namespace jam::checks
