#pragma once
// The integrators a run can choose, in one list: which dynamics each integrates, its cost in
// force evaluations per step and its order in dt. Validation (sim_config.cpp), the default per
// dynamics (SimConfig::resolved_integrator), the cost estimates of campaigns and benchmarks
// and the help of --integrator all read it. The classes themselves are in one header each
// (overdamped_euler.hpp, overdamped_heun.hpp, overdamped_chebyshev.hpp, inertial_verlet.hpp),
// listed in integrators.hpp and dispatched once per run in sim/run/compression_run.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace jam {

struct IntegratorInfo {
  std::string_view name;      // --integrator value, the classes' kName
  std::string_view dynamics;  // --dynamics it integrates
  int force_evaluations;      // per step: what a step costs (0: adaptive, see below)
  int order;                  // global error ~ dt^order
  bool is_default;            // a default of its dynamics ...
  double default_max_rate;    // ... at compression rates up to this (the lowest bound wins)
  // A run's resident memory per particle, 2D and 3D, one thread: the system, neighbor list and
  // everything the integrator keeps (whole jam sim processes at N = 2^18 less N = 256, Poisson
  // starts at phi 0.80 and 0.60; tests/test_memory_estimate.py). The run limits' estimate
  // (run_limits.cpp) adds its headroom.
  std::array<double, 2> bytes_per_particle;
};

inline constexpr double kAnyRate = 1e300;

// The Chebyshev integrator, at its rate-dependent default tolerance (sim_config.hpp,
// auto_tolerance), is the overdamped default at every rate: measured against Heun at dt 0.1
// (docs/performance.md, the Chebyshev integrator) 3.2x faster at 1e-3 and 4.9x at 1e-4 (2D,
// N = 4096, tolerance 1e-2), 6.0x at 1e-5 (1e-3), 6.4x at 1e-6 and 12.7x at 1e-7 (1e-4), the
// ensemble-mean pressure within 2.3e-4 of a converged reference throughout. Heun at dt 0.1 was
// the default before (2.5-4x cheaper than Euler at equal accuracy).
inline constexpr std::array<IntegratorInfo, 4> kIntegrators = {{
    {"euler", "overdamped", 1, 1, false, 0.0, {103, 141}},
    {"heun", "overdamped", 2, 2, false, 0.0, {135, 190}},
    // Runge-Kutta-Chebyshev with error control: its steps and stages adapt to the run. Its
    // memory: five stage arrays and the Lanczos estimate's four vectors and contact terms.
    {"chebyshev", "overdamped", 0, 2, true, kAnyRate, {296, 482}},
    // Forces at the new positions serve the next step too.
    {"verlet", "inertial", 1, 2, true, kAnyRate, {135, 191}},
}};

/// The dynamics, in the order of the list ("overdamped", "inertial").
inline constexpr std::array<std::string_view, 2> kDynamics = {"overdamped", "inertial"};

/// The entry named `name`, or nullptr.
inline const IntegratorInfo* find_integrator(std::string_view name) {
  for (const auto& i : kIntegrators)
    if (i.name == name) return &i;
  return nullptr;
}

/// The default integrator of `dynamics` at compression rate `rate` ("" for an unknown
/// dynamics): of its defaults whose range holds the rate, the one of the narrowest range.
inline std::string_view default_integrator(std::string_view dynamics, double rate = kAnyRate) {
  const IntegratorInfo* best = nullptr;
  for (const auto& i : kIntegrators) {
    if (i.dynamics == dynamics && i.is_default && rate <= i.default_max_rate &&
        (!best || i.default_max_rate < best->default_max_rate))
      best = &i;
  }
  return best ? best->name : std::string_view{};
}

/// Whether the integrator chooses its own steps (--dt is then its first step).
inline bool is_adaptive_integrator(std::string_view name) {
  const IntegratorInfo* i = find_integrator(name);
  return i && i->force_evaluations == 0;
}

/// The error-controlled integrator of `dynamics` ("" when it has none): what a convergence
/// re-run uses, whatever step the campaign took.
inline std::string_view adaptive_integrator_of(std::string_view dynamics) {
  for (const auto& i : kIntegrators)
    if (i.dynamics == dynamics && i.force_evaluations == 0) return i.name;
  return {};
}

/// Measured resident bytes per particle of a run with integrator `name` in `dim` dimensions,
/// one thread (the largest entry's for an unknown name).
inline double bytes_per_particle(std::string_view name, int dim) {
  const std::size_t d = dim == 2 ? 0 : 1;
  if (const IntegratorInfo* i = find_integrator(name)) return i->bytes_per_particle[d];
  double most = 0.0;
  for (const auto& i : kIntegrators) most = std::max(most, i.bytes_per_particle[d]);
  return most;
}

/// Force evaluations per step of the integrator `name` (1 for an unknown name).
inline int force_evaluations_per_step(std::string_view name) {
  const IntegratorInfo* i = find_integrator(name);
  return i ? i->force_evaluations : 1;
}

/// "a", "a or b", "a, b or c": words joined as the one-line errors list allowed values.
template <class Words>
std::string or_list(const Words& words) {
  std::string out;
  std::size_t k = 0;
  for (const auto& w : words) {
    if (k > 0) out += k + 1 == std::size(words) ? " or " : ", ";
    out += std::string(w);
    ++k;
  }
  return out;
}

/// The integrators of `dynamics`, in the order of the list.
inline std::vector<std::string_view> integrators_of(std::string_view dynamics) {
  std::vector<std::string_view> names;
  for (const auto& i : kIntegrators)
    if (i.dynamics == dynamics) names.push_back(i.name);
  return names;
}

/// The help of --integrator: "euler, heun or chebyshev (overdamped; default chebyshev), verlet
/// (inertial)".
inline std::string integrator_help() {
  std::string out;
  for (const auto dynamics : kDynamics) {
    const auto names = integrators_of(dynamics);
    if (!out.empty()) out += ", ";
    out += or_list(names) + " (" + std::string(dynamics);
    if (names.size() > 1) out += "; default " + std::string(default_integrator(dynamics));
    out += ")";
  }
  return out;
}

}  // namespace jam
