#pragma once
// The part of an integrator's state that must survive a checkpoint for a resumed run to be
// bitwise identical to an uninterrupted one: named arrays of doubles. Euler and Heun keep
// nothing between steps; velocity Verlet keeps velocities and the last total force; the
// Chebyshev integrator its next step size and its estimate of the stiffest mode.
#include <string>
#include <utility>
#include <vector>

namespace jam {

using StepperState = std::vector<std::pair<std::string, std::vector<double>>>;

/// What constructs any integrator (integrators.hpp): each takes what it needs.
struct StepperOptions {
  double quality_factor = 0.0;  // inertial: Q
  double tolerance = 0.0;       // adaptive: local error per step (d_s)
  double first_step = 0.0;      // adaptive: the first step tried (t0)
};

}  // namespace jam
