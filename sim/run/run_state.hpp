#pragma once
// Where a compression run is: the phase, the step counters and the output points recorded so
// far. Together with the particles and the integrator's StepperState it is everything a
// checkpoint holds; nothing else influences the numbers a run produces.
#include <cstdint>
#include <vector>

#include "sim/observables/jamming_point.hpp"
#include "sim/observables/observables.hpp"

namespace jam {

template <int D>
struct RunState {
  enum Phase : std::int64_t { kRelaxing = 0, kCompressing = 1 };
  std::int64_t phase = kRelaxing;
  std::int64_t relax_steps = 0;
  bool relax_converged = false;
  std::int64_t steps = 0;  // compression steps done
  // The integrator's force evaluations while compressing (not the measurements at output
  // points, one each), across resumes: the machine-independent cost the planner models.
  std::int64_t force_evaluations = 0;
  std::int64_t next_output = 0;  // index of the next output time
  // Time reached by an adaptive integrator's accumulated steps (compression, relaxation);
  // fixed-step integrators use t = k dt from the step counts instead.
  double time = 0.0;
  double relax_time = 0.0;
  // CPU seconds of the run's thread up to the checkpoint, over every attempt: a resumed run's
  // cost includes those before it stopped (thread_cpu_clock.hpp).
  double cpu_seconds = 0.0;
  std::vector<Observables<D>> points;
  std::vector<SavedConfiguration> saved;  // for the jamming point, when asked for
  JammingAnswers jamming_answers;         // of a search stopped on request (jamming_point.hpp)
};

}  // namespace jam
