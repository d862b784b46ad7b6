#pragma once
// One compression run, from configuration to run file:
//   configuration (generated or read) -> relaxation at zero rate -> compression at the rate,
//   observables at output points -> HDF5 run file (atomic).
#include <cstddef>
#include <vector>

#include "sim/run/sim_config.hpp"

namespace jam {

/// Everything `jam sim` prints after a run.
struct RunSummary {
  std::size_t n = 0;
  std::size_t steps = 0;  // compression steps
  std::size_t relax_steps = 0;
  bool relax_converged = true;
  std::size_t neighbor_builds = 0;
  std::size_t output_points = 0;
  double initial_box_length = 0.0;
  double phi_init = 0.0;
  double final_packing_fraction = 0.0;
  double final_pressure = 0.0;
  double final_contacts_per_particle = 0.0;
  double final_energy_per_particle = 0.0;
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;  // compression phase, force evaluations counted once
};

/// Runs the compression described by the validated config and writes config.out.
RunSummary run_compression(const SimConfig& config);

}  // namespace jam
