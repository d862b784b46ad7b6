#pragma once
// The single runs of `jam bench accuracy`: relaxed starts, jam compressions that land exactly
// on the packings, and LAMMPS compressions read at them. See accuracy.hpp for the protocol.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/accuracy.hpp"
#include "sim/model/particles.hpp"

namespace jam::bench {

/// A relaxed start: scaled positions (D arrays of N), types, box length.
struct Start {
  int dim = 2;
  std::vector<std::vector<double>> s;
  std::vector<std::uint8_t> type;
  std::vector<std::uint32_t> id;
  double box_length = 0.0;
  double energy_per_particle = 0.0;  // left after the relaxation
};

/// A start holding these particles in a box of this length (energy not measured).
template <int D>
Start start_from(const ParticleData<D>& p, double box_length) {
  Start start;
  start.dim = D;
  for (int d = 0; d < D; ++d) start.s.push_back(p.s[d]);
  start.type = p.type;
  start.id = p.id;
  start.box_length = box_length;
  return start;
}

Start relaxed_start(int dim, std::int64_t n, std::uint64_t seed, double phi, double relax_time);

/// Writes the start as a LAMMPS data file with the masses of the given quality factor Q.
void write_start(const Start& start, double quality_factor, const std::string& path);

/// jam from the start at the rate: returns the pressures at the packings and the wall time
/// of the compression. integrator: euler | heun | verlet (quality_factor used for verlet).
struct RunResult {
  std::array<double, 3> pressure{};
  std::array<double, 3> pressure_shifted{};  // LAMMPS only: the line of step m read at (m-1) dt
  double wall = 0.0;
  double process_wall = 0.0;  // LAMMPS: the whole lmp process (start-up and reading included)
};
RunResult run_jam(const Start& start, double rate, const std::string& integrator,
                  double quality_factor, double tolerance, double dt,
                  const std::array<double, 3>& phi);

/// LAMMPS from the data file (in dir) at the rate and dt. pressure: the thermo as printed
/// (step m at time m dt); pressure_shifted: read at (m-1) dt with the volume of that time.
RunResult run_lammps_compression(const std::filesystem::path& dir,
                                 const std::filesystem::path& reference, const std::string& data,
                                 const std::string& log, int dim, double rate, double dt,
                                 double phi_start, const std::array<double, 3>& phi);

}  // namespace jam::bench
