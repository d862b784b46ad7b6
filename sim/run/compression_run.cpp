#include "sim/run/compression_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "sim/dynamics/inertial_verlet.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/run_file.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/progress.hpp"

namespace jam {
namespace {

/// Fails early, before any work, if the output cannot be written.
void check_writable(const std::string& option, const std::string& path) {
  const std::string probe = AtomicFile::temporary_name(path);
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f) throw ConfigError(fmt::format("--{} {}: cannot write there", option, path));
  std::fclose(f);
  std::remove(probe.c_str());
}

template <int D>
struct Start {
  ParticleData<D> particles;
  double box_length = 0.0;
  std::string description;
};

template <int D>
Start<D> make_start(const SimConfig& c, const Species<D>& species) {
  Start<D> start;
  if (!c.read_lammps_data.empty()) {
    LammpsData<D> data = read_lammps_data<D>(c.read_lammps_data);
    start.particles = std::move(data.particles);
    start.box_length = data.box_length;
    start.description = c.read_lammps_data;
    sort_spatially(start.particles, species, start.box_length);
  } else {
    start.particles = random_configuration<D>(static_cast<std::size_t>(c.n), c.seed);
    start.box_length = CompressingBox<D>::length_for_packing(
        total_particle_volume(start.particles, species), c.phi_init);
    start.description = "random";
    sort_spatially(start.particles, species, start.box_length);
    for (std::size_t i = 0; i < start.particles.size(); ++i) {
      start.particles.id[i] = static_cast<std::uint32_t>(i + 1);
    }
  }
  return start;
}

/// Output times: t = 0, then the first step at or after each packing k * phi_step strictly
/// between phi_init and phi_stop, then exactly phi_stop.
template <int D>
std::vector<double> output_times(const CompressingBox<D>& box, double phi_init, double phi_stop,
                                 double phi_step) {
  std::vector<double> t;
  for (auto k = static_cast<long long>(std::floor(phi_init / phi_step)) + 1;; ++k) {
    const double phi = static_cast<double>(k) * phi_step;
    if (phi >= phi_stop * (1.0 - 1e-12)) break;
    if (phi > phi_init * (1.0 + 1e-12)) t.push_back(box.time_at_packing(phi));
  }
  t.push_back(box.time_at_packing(phi_stop));
  return t;
}

template <int D, class Stepper>
RunSummary integrate(const SimConfig& c, System<D>& sys, Stepper& stepper, RunMetadata meta) {
  using Clock = std::chrono::steady_clock;
  const std::size_t n = sys.size();
  const double rate = sys.box.compression_rate;

  Progress progress(!c.quiet, c.phi_stop);
  // Relaxation at zero rate (paper's supplement, "Compression Protocol").
  if (c.relax) {
    const double target_energy = c.resolved_relax_energy();
    sys.box.compression_rate = 0.0;
    double t = 0.0;
    std::size_t k = 0;
    meta.relax_converged = false;
    while (true) {
      if (k % 100 == 0) {
        const auto obs = measure(sys, 0.0, false);
        if (!std::isfinite(obs.energy_per_particle)) {
          throw std::runtime_error(fmt::format(
              "relaxation became unstable (non-finite energy) with --dt {:g}; reduce --dt", c.dt));
        }
        progress.update_relaxation(obs.energy_per_particle, target_energy, t);
        if (obs.energy_per_particle <= target_energy) {
          meta.relax_converged = true;
          break;
        }
        if (t >= c.relax_time_max) break;
      }
      stepper.step(sys, t, c.dt);
      ++k;
      t = static_cast<double>(k) * c.dt;
    }
    meta.relax_steps = static_cast<std::int64_t>(k);
    sys.box.compression_rate = rate;
    stepper.reset();
  }

  auto write_configuration = [&](const std::string& path, double t, const char* what) {
    const auto masses = sys.species.masses(c.q);
    write_lammps_data(path, sys.particles, sys.box.length(t), masses[0], masses[1],
                      fmt::format("jam {} configuration, dim {} n {} phi {:.17g} seed {}", what, D,
                                  n, sys.box.packing_fraction(t), c.seed));
  };
  if (!c.write_lammps_data.empty()) write_configuration(c.write_lammps_data, 0.0, "initial");

  const std::vector<double> targets = output_times(sys.box, meta.phi_init, c.phi_stop, c.phi_step);
  const double t_stop = targets.back();
  std::vector<Observables<D>> points;
  points.reserve(targets.size() + 1);
  auto record = [&](double t) {
    points.push_back(measure(sys, t, c.rattlers));
    if (!std::isfinite(points.back().pressure)) {
      throw std::runtime_error(fmt::format(
          "the dynamics became unstable (non-finite pressure at phi {:.5f}) with --dt {:g}; "
          "reduce --dt",
          points.back().packing_fraction, c.dt));
    }
  };
  record(0.0);

  const auto wall_start = Clock::now();
  const std::size_t builds_before = sys.neighbors.builds();
  std::size_t next = 0, step = 0;
  double t = 0.0;
  while (next < targets.size()) {
    // Fixed steps t_k = k dt (never accumulated); the last step is shortened to land on
    // t_stop exactly, and a sliver shorter than 1e-6 dt is folded into it.
    double h = c.dt;
    double t_after = static_cast<double>(step + 1) * c.dt;
    if (t_stop - t_after < 1e-6 * c.dt) {
      h = t_stop - t;
      t_after = t_stop;
    }
    stepper.step(sys, t, h);
    ++step;
    t = t_after;
    bool due = false;
    while (next < targets.size() && t >= targets[next]) {
      due = true;
      ++next;
    }
    if (due) record(t);
    if ((step & 255) == 0) {
      progress.update(t / t_stop, sys.box.packing_fraction(t), step, n);
    }
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();

  meta.steps = static_cast<std::int64_t>(step);
  if (!c.write_final_lammps_data.empty()) {
    write_configuration(c.write_final_lammps_data, t_stop, "final");
  }
  write_run_file<D>(c.out, c, meta, points);

  RunSummary s;
  s.n = n;
  s.steps = step;
  s.relax_steps = static_cast<std::size_t>(meta.relax_steps);
  s.relax_converged = meta.relax_converged;
  s.neighbor_builds = sys.neighbors.builds() - builds_before;
  s.output_points = points.size();
  s.initial_box_length = meta.initial_box_length;
  s.phi_init = meta.phi_init;
  s.final_packing_fraction = points.back().packing_fraction;
  s.final_pressure = points.back().pressure;
  s.final_contacts_per_particle = points.back().contacts_per_particle;
  s.final_energy_per_particle = points.back().energy_per_particle;
  s.wall_seconds = wall;
  s.particle_steps_per_second = wall > 0 ? static_cast<double>(step * n) / wall : 0.0;
  return s;
}

template <int D>
RunSummary run_dimension(const SimConfig& c) {
  const Species<D> species(c.diameter_ratio);
  Start<D> start = make_start<D>(c, species);
  CompressingBox<D> box;
  box.initial_length = start.box_length;
  box.compression_rate = c.compression_rate;
  box.particle_volume = total_particle_volume(start.particles, species);

  RunMetadata meta;
  meta.n = static_cast<std::int64_t>(start.particles.size());
  meta.phi_init = box.packing_fraction(0.0);
  meta.initial_box_length = start.box_length;
  meta.integrator = c.resolved_integrator();
  meta.initial_configuration = start.description;
  if (meta.phi_init >= c.phi_stop) {
    throw ConfigError(fmt::format("--phi-stop {:g}: must be above the packing of {} ({:.6g})",
                                  c.phi_stop, start.description, meta.phi_init));
  }
  SimConfig checked = c;
  checked.n = meta.n;
  validate_box(checked, CompressingBox<D>::length_for_packing(box.particle_volume, c.phi_stop),
               species.max_contact_distance);

  System<D> sys(std::move(start.particles), species, box, c.skin);
  const std::size_t n = sys.size();
  if (meta.integrator == "euler") {
    OverdampedEuler<D> stepper(n);
    return integrate(c, sys, stepper, meta);
  }
  if (meta.integrator == "heun") {
    OverdampedHeun<D> stepper(n);
    return integrate(c, sys, stepper, meta);
  }
  InertialVerlet<D> stepper(n, c.q);
  return integrate(c, sys, stepper, meta);
}

}  // namespace

RunSummary run_compression(const SimConfig& c) {
  validate(c);
  check_writable("out", c.out);
  if (!c.write_lammps_data.empty()) check_writable("write-lammps-data", c.write_lammps_data);
  if (!c.write_final_lammps_data.empty()) {
    check_writable("write-final-lammps-data", c.write_final_lammps_data);
  }
  return c.dim == 2 ? run_dimension<2>(c) : run_dimension<3>(c);
}

}  // namespace jam
