#pragma once
// Checkpoints of a running compression: "<run file>.checkpoint", HDF5, written atomically
// (temporary name, then rename), so a kill at any moment leaves either the previous or the
// new checkpoint. A checkpoint carries the run's fingerprint (every parameter that changes
// its numbers) and is only ever resumed by the run with the same fingerprint. It is sealed
// with a checksum of every byte (sealed_file.hpp); one that fails it, or has no seal, is
// CorruptCheckpoint: discarded with a warning, never resumed.
#include <optional>
#include <stdexcept>
#include <string>

#include "sim/dynamics/stepper_state.hpp"
#include "sim/model/particles.hpp"
#include "sim/run/run_state.hpp"

namespace jam {

/// A checkpoint (or relaxed-start cache) that exists but cannot be read back: written by a
/// process that died in the middle, or damaged since. The run starts afresh instead.
struct CorruptCheckpoint : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A sound checkpoint (or start) written by a run with other parameters (another fingerprint).
struct ForeignCheckpoint : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <int D>
struct Checkpoint {
  RunState<D> state;
  ParticleData<D> particles;
  StepperState stepper;
};

inline std::string checkpoint_path(const std::string& run_file) {
  return run_file + ".checkpoint";
}

template <int D>
void write_checkpoint(const std::string& path, const std::string& fingerprint,
                      const RunState<D>& state, const ParticleData<D>& particles,
                      const StepperState& stepper);

/// The checkpoint at path, or nothing if there is none. Throws ForeignCheckpoint if it belongs
/// to another run (different fingerprint), CorruptCheckpoint if it fails its seal or cannot be
/// read.
template <int D>
std::optional<Checkpoint<D>> read_checkpoint(const std::string& path,
                                             const std::string& fingerprint);

}  // namespace jam
