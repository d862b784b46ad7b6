#pragma once
// The part of an integrator's state that must survive a checkpoint for a resumed run to be
// bitwise identical to an uninterrupted one: named arrays of doubles. Euler and Heun keep
// nothing between steps; velocity Verlet keeps velocities and the last total force.
#include <string>
#include <utility>
#include <vector>

namespace jam {

using StepperState = std::vector<std::pair<std::string, std::vector<double>>>;

}  // namespace jam
