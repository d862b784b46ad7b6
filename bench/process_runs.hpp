#pragma once
// The whole-process runs of `jam bench accuracy` (its headline): `jam sim` started as a user
// starts it, from a LAMMPS data file, at the campaigns' output grid, timed from spawn to exit
// (start-up, reading the start, every output point, the run file). See accuracy.hpp.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/accuracy_runs.hpp"

namespace jam::bench {

/// The output spacing of every stored campaign, which the whole-process runs write.
inline constexpr double kCampaignPhiStep = 0.0005;

/// `jam sim --dim D --read-lammps-data DATA --relax 0 --rate R --phi-stop phi[2] --phi-step 0.0005
/// [extra] --out OUT --quiet --checkpoint-interval 0` in `dir` (this executable, argument
/// vector): the pressures at the packings (output points of the grid; phi[2] is the last) and
/// the process's wall time. Throws naming the command when it fails or a packing is missing.
RunResult run_jam_process(const std::filesystem::path& dir, int dim, const std::string& data,
                          const std::string& out, double rate,
                          const std::vector<std::string>& extra, const std::array<double, 3>& phi);

/// The packings must lie on the output grid (multiples of kCampaignPhiStep): throws otherwise.
void require_on_grid(const std::array<double, 3>& phi);

/// A start that was not relaxed: the random configuration at phi as generated (overlaps and
/// all), as LAMMPS compresses its own random starts.
Start unrelaxed_start(int dim, std::int64_t n, std::uint64_t seed, double phi);

}  // namespace jam::bench
