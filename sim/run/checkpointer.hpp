#pragma once
// A run's checkpoints: where they live, when one is due, and how one is read back. The state
// a checkpoint holds is RunState + particles + the integrator's StepperState (run_state.hpp);
// with them a resumed run continues bitwise as if it had never stopped.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "sim/io/checkpoint.hpp"
#include "sim/io/output_path.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/run_state.hpp"
#include "sim/run/thread_cpu_clock.hpp"

namespace jam {

/// A checkpoint or start cache that cannot be read back, fails its checksum or holds another
/// number of particles is removed with a warning naming it, and the run starts afresh (the
/// results are those of an uninterrupted run either way); it is never resumed from.
/// A relaxed start is a cache keyed by its file name: one of other parameters (a campaign rerun
/// at another dt) is stale and replaced the same way (`replace_foreign`); a run's own checkpoint
/// of other parameters is refused instead, since the same --out was probably meant for them.
template <int D>
std::optional<Checkpoint<D>> read_checkpoint_or_warn(const std::string& path,
                                                     const std::string& fingerprint, std::size_t n,
                                                     bool replace_foreign = false) {
  // Not a regular file (a FIFO would block the open for ever): refused, and left alone.
  check_input_file("checkpoint", path);
  std::string problem;
  try {
    auto saved = read_checkpoint<D>(path, fingerprint);
    if (!saved || saved->particles.size() == n) return saved;
    problem = fmt::format("{} particles, not {}", saved->particles.size(), n);
  } catch (const CorruptCheckpoint& e) {
    problem = e.what();
  } catch (const ForeignCheckpoint& e) {
    if (!replace_foreign) throw;
    problem = "written with other parameters";
  }
  fmt::print(stderr, "jam: warning: {} cannot be trusted ({}); removed, starting afresh\n", path,
             problem);
  std::remove(path.c_str());
  return std::nullopt;
}

/// The checkpoints of one run (<out>.checkpoint, tagged with the run's fingerprint). They are
/// taken between steps, at most every 256 steps, when the wall-time interval has passed or a
/// stop was requested.
template <int D>
class Checkpointer {
 public:
  using Clock = std::chrono::steady_clock;

  Checkpointer(const std::string& run_file, std::string fingerprint, const RunControl& control)
      : path_(checkpoint_path(run_file)),
        fingerprint_(std::move(fingerprint)),
        control_(control),
        interval_(control.checkpoint_interval_seconds),
        last_(Clock::now()),
        cpu_start_(thread_cpu_seconds()) {}

  /// The run continues from a checkpoint whose attempts took `cpu_seconds` before this one.
  void resumed_after(double cpu_seconds) { cpu_before_ = cpu_seconds; }

  /// The run's own checkpoint, if a trustworthy one exists.
  std::optional<Checkpoint<D>> read(std::size_t n) const {
    return read_checkpoint_or_warn<D>(path_, fingerprint_, n);
  }

  /// Writes a checkpoint when one is due or a stop was requested (with the run's CPU seconds
  /// so far in st.cpu_seconds). True when the run must stop.
  bool checkpoint_if_due(RunState<D>& st, const ParticleData<D>& particles,
                         const StepperState& stepper) {
    const bool stop = control_.stop && control_.stop->load();
    const bool due = control_.checkpoint_interval_seconds > 0 && Clock::now() - last_ >= interval_;
    if (stop || due) {
      st.cpu_seconds = cpu_before_ + (thread_cpu_seconds() - cpu_start_);
      write_checkpoint(path_, fingerprint_, st, particles, stepper);
      last_ = Clock::now();
    }
    return stop;
  }

  /// Once the run file is written the checkpoint has nothing left to resume.
  void remove() const { std::remove(path_.c_str()); }

 private:
  std::string path_;
  std::string fingerprint_;
  const RunControl& control_;
  std::chrono::duration<double> interval_;
  Clock::time_point last_;
  double cpu_start_;         // this thread's CPU seconds when this attempt began
  double cpu_before_ = 0.0;  // of the attempts before it (from the checkpoint resumed)
};

}  // namespace jam
