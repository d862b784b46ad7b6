#pragma once
// One compression run, from configuration to run file:
//   configuration (generated or read) -> relaxation at zero rate -> compression at the rate,
//   observables at output points -> HDF5 run file (atomic).
#include <atomic>
#include <cstddef>
#include <cstdint>
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
  std::uint64_t force_evaluations = 0;  // by this invocation (relaxation, compression)
  // Force evaluations x N of this invocation, the jamming search's included: what it added to
  // RunControl::particle_steps (a campaign's progress).
  std::uint64_t counted_particle_steps = 0;
  std::uint64_t rejected_steps = 0;  // adaptive integrators: steps tried again shorter
  std::size_t output_points = 0;
  double initial_box_length = 0.0;
  double phi_init = 0.0;
  double final_packing_fraction = 0.0;
  double final_pressure = 0.0;
  double final_contacts_per_particle = 0.0;
  double final_energy_per_particle = 0.0;
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;  // relaxation + compression steps of this invocation
  bool resumed = false;                    // continued from a checkpoint
  double earlier_cpu_seconds = 0.0;  // CPU seconds of the attempts before it (its checkpoint's)
  bool interrupted = false;          // stopped on request; a checkpoint holds the state
  bool start_only = false;  // stopped once its chained start was written (RunControl::start_only)
};

/// How a run is driven from outside: checkpoints, stop requests, progress accounting.
struct RunControl {
  /// Wall time between checkpoints ("<out>.checkpoint"); 0 disables them.
  double checkpoint_interval_seconds = 300.0;
  /// When it becomes true the run writes a checkpoint and returns with interrupted = true.
  const std::atomic<bool>* stop = nullptr;
  /// Incremented by the particle-steps done (force evaluations x N, the planner's unit), for a
  /// campaign's progress display.
  std::atomic<std::uint64_t>* particle_steps = nullptr;
  /// Only the chained start (write_start): the run stops once it has written it, writes no run
  /// file and leaves an existing one as it is; its checkpoint is removed. For a campaign whose
  /// run is done but whose start for the next slower rate was lost: the same trajectory up to
  /// the start's packing, so the same start, bit for bit, for a fraction of the run's cost.
  bool start_only = false;
};

/// Runs the compression described by the config and writes config.out. A checkpoint of the
/// same run left by an earlier, interrupted invocation is resumed; the result is bitwise
/// identical to an uninterrupted run.
RunSummary run_compression(const SimConfig& config, const RunControl& control = {});

/// For a generated start (N/2 small and N/2 big): whether its box at phi_stop holds twice the
/// interaction range (validate_box), known before any particle exists. A campaign checks each
/// of its sizes so, and a bad combination is refused at once instead of becoming failed runs.
void validate_generated_box(const SimConfig& config);

}  // namespace jam
