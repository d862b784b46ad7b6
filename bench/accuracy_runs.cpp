#include "bench/accuracy_runs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "bench/lammps_bench.hpp"
#include "sim/dynamics/inertial_verlet.hpp"
#include "sim/dynamics/integrators.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/observables/observables.hpp"

namespace jam::bench {
namespace {

using Clock = std::chrono::steady_clock;
// The relaxation stops at 1e-10 per particle or after the given time (near jamming a full
// relaxation takes thousands of t0).
constexpr double kRelaxDt = 0.01, kRelaxEnergy = 1e-10;

template <int D>
ParticleData<D> particles_of(const Start& start) {
  ParticleData<D> p;
  for (int d = 0; d < D; ++d) p.s[d] = start.s[d];
  p.type = start.type;
  p.id = start.id;
  return p;
}

template <int D>
Start relaxed(std::int64_t n, std::uint64_t seed, double phi, double relax_time) {
  const Species<D> species;
  RandomStart<D> r = random_start<D>(static_cast<std::size_t>(n), seed, species, phi);
  System<D> sys(std::move(r.particles), species,
                CompressingBox<D>{r.box_length, 0.0, r.particle_volume}, 0.3);
  OverdampedEuler<D> stepper(sys.size());
  for (long k = 0;; ++k) {
    if (k % 100 == 0) {
      const double e = measure(sys, 0.0, false).energy_per_particle;
      if (e <= kRelaxEnergy || k * kRelaxDt >= relax_time) break;
    }
    stepper.step(sys, 0.0, kRelaxDt);
  }
  Start start = start_from(sys.particles, r.box_length);
  start.energy_per_particle = measure(sys, 0.0, false).energy_per_particle;
  return start;
}

template <int D, class Stepper>
RunResult compress(System<D>& sys, Stepper& stepper, double dt, const std::array<double, 3>& phi) {
  RunResult r;
  const auto start = Clock::now();
  double t = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double target = sys.box.time_at_packing(phi[k]);
    // Fixed steps; the one that would pass the target is shortened to land on it (a sliver
    // shorter than 1e-6 dt is folded into the step before).
    while (t < target) {
      if constexpr (is_adaptive<Stepper>()) {  // its own steps, landing on the target
        const double h = stepper.step(sys, t, target - t);
        t = h == target - t ? target : t + h;
        continue;
      }
      double h = dt;
      if (target - (t + h) < 1e-6 * dt) h = target - t;
      stepper.step(sys, t, h);
      t = h == dt ? t + dt : target;
    }
    r.pressure[k] = measure(sys, target, false).pressure;
  }
  r.wall = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

template <int D>
RunResult jam_run(const Start& start, double rate, const std::string& integrator,
                  double quality_factor, double tolerance, double dt,
                  const std::array<double, 3>& phi) {
  const Species<D> species;
  ParticleData<D> p = particles_of<D>(start);
  const double volume = total_particle_volume(p, species);
  System<D> sys(std::move(p), species, CompressingBox<D>{start.box_length, rate, volume}, 0.3);
  return with_integrator<D>(integrator, sys.size(), StepperOptions{quality_factor, tolerance, dt},
                            [&](auto& stepper) { return compress(sys, stepper, dt, phi); });
}

/// Quadratic (three-point Lagrange) interpolation of y(x) at x0, x sorted ascending.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double x0) {
  if (x.size() < 3 || x0 < x.front() || x0 > x.back())
    throw std::runtime_error(fmt::format("LAMMPS thermo does not cover time {:g}", x0));
  std::size_t k = static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), x0) - x.begin());
  k = std::clamp<std::size_t>(k, 1, x.size() - 2);
  const double a = x[k - 1], b = x[k], c = x[k + 1];
  return y[k - 1] * (x0 - b) * (x0 - c) / ((a - b) * (a - c)) +
         y[k] * (x0 - a) * (x0 - c) / ((b - a) * (b - c)) +
         y[k + 1] * (x0 - a) * (x0 - b) / ((c - a) * (c - b));
}

}  // namespace

Start relaxed_start(int dim, std::int64_t n, std::uint64_t seed, double phi, double relax_time) {
  return dim == 2 ? relaxed<2>(n, seed, phi, relax_time) : relaxed<3>(n, seed, phi, relax_time);
}

void write_start(const Start& start, double quality_factor, const std::string& path) {
  if (start.dim == 2) {
    const auto m = Species<2>().masses(quality_factor);
    write_lammps_data(path, particles_of<2>(start), start.box_length, m[0], m[1],
                      "jam bench accuracy start");
  } else {
    const auto m = Species<3>().masses(quality_factor);
    write_lammps_data(path, particles_of<3>(start), start.box_length, m[0], m[1],
                      "jam bench accuracy start");
  }
}

RunResult run_jam(const Start& start, double rate, const std::string& integrator,
                  double quality_factor, double tolerance, double dt,
                  const std::array<double, 3>& phi) {
  return start.dim == 2 ? jam_run<2>(start, rate, integrator, quality_factor, tolerance, dt, phi)
                        : jam_run<3>(start, rate, integrator, quality_factor, tolerance, dt, phi);
}

RunResult run_lammps_compression(const std::filesystem::path& dir,
                                 const std::filesystem::path& reference, const std::string& data,
                                 const std::string& log, int dim, double rate, double dt,
                                 double phi_start, const std::array<double, 3>& phi) {
  const double t_end = std::log(phi[2] / phi_start) / (dim * rate);
  LammpsRequest r;
  r.directory = dir;
  r.reference = reference;
  r.data = data;
  r.log = log;
  r.dim = dim;
  r.rate = rate;
  r.dt = dt;
  r.every = std::max(1L, std::lround(0.05 / dt));
  r.steps = (static_cast<long>(std::ceil(t_end / dt)) / r.every + 3) * r.every;
  const auto started = Clock::now();
  const LammpsResult l = run_lammps(r);
  const double process_wall = std::chrono::duration<double>(Clock::now() - started).count();
  // Line m: forces at the box of time (m-1) dt, volume of time m dt.
  std::vector<double> t, p, t_shifted, p_shifted;
  const double volume_ratio = std::exp(dim * rate * dt);  // V((m-1) dt) / V(m dt)
  for (std::size_t k = 0; k < l.step.size(); ++k) {
    t.push_back(l.step[k] * dt);
    p.push_back(l.pressure[k]);
    if (l.step[k] < 1) continue;
    t_shifted.push_back((l.step[k] - 1) * dt);
    p_shifted.push_back(l.pressure[k] / volume_ratio);
  }
  RunResult res;
  res.wall = l.loop_seconds;
  res.process_wall = process_wall;
  for (int k = 0; k < 3; ++k) {
    const double time = std::log(phi[k] / phi_start) / (dim * rate);
    res.pressure[k] = interpolate(t, p, time);
    res.pressure_shifted[k] = interpolate(t_shifted, p_shifted, time);
  }
  return res;
}

}  // namespace jam::bench
