#include "sim/run/compression_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "sim/dynamics/inertial_verlet.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/progress.hpp"
#include "sim/run/run_state.hpp"
#include "sim/run/stability_guard.hpp"

namespace jam {
namespace {

/// Fails early, before any work, if the output is not a regular file or a new name
/// (output_path.hpp) or cannot be written; returns the path to write (a link's target).
std::string checked_writable(const std::string& option, const std::string& path) {
  const std::string target = checked_output_file(option, path);
  const std::string probe = AtomicFile::temporary_name(target);
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f) {
    throw ConfigError(
        fmt::format("--{} {}: cannot write there: {}", option, path, std::strerror(errno)));
  }
  std::fclose(f);
  std::remove(probe.c_str());
  return target;
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
    RandomStart<D> r = random_start<D>(static_cast<std::size_t>(c.n), c.seed, species, c.phi_init);
    start.particles = std::move(r.particles);
    start.box_length = r.box_length;
    start.description = "random";
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

template <int D, class Stepper>
RunSummary integrate(const SimConfig& c, const RunControl& control, System<D>& sys,
                     Stepper& stepper, RunMetadata meta) {
  using Clock = std::chrono::steady_clock;
  const std::size_t n = sys.size();
  const double rate = sys.box.compression_rate;
  const std::string checkpoint_file = checkpoint_path(c.out);
  const std::string run_fingerprint = fingerprint(c);

  RunState<D> st;
  bool resumed = false;
  if (auto saved = read_checkpoint_or_warn<D>(checkpoint_file, run_fingerprint, n)) {
    sys.particles = std::move(saved->particles);
    sys.neighbors.invalidate();
    stepper.load_state(saved->stepper);
    st = std::move(saved->state);
    resumed = true;
  }

  // Checkpoints are taken between steps, every 256 steps at most, when the wall-time interval
  // has passed or a stop was requested. Returns true when the run must stop.
  auto last_checkpoint = Clock::now();
  const auto interval = std::chrono::duration<double>(control.checkpoint_interval_seconds);
  auto checkpoint_if_due = [&]() {
    const bool stop = control.stop && control.stop->load();
    const bool due =
        control.checkpoint_interval_seconds > 0 && Clock::now() - last_checkpoint >= interval;
    if (stop || due) {
      write_checkpoint(checkpoint_file, run_fingerprint, st, sys.particles, stepper.save_state());
      last_checkpoint = Clock::now();
    }
    return stop;
  };
  auto count_steps = [&](std::size_t steps) {
    if (control.particle_steps) control.particle_steps->fetch_add(steps * n);
  };
  StabilityGuard<D> stability(c, sys.species);
  RunSummary summary;
  summary.n = n;
  summary.resumed = resumed;
  summary.phi_init = meta.phi_init;
  summary.initial_box_length = meta.initial_box_length;

  Progress progress(!c.quiet, c.phi_stop);
  const auto wall_start = Clock::now();
  std::size_t steps_here = 0;  // relaxation and compression steps done by this invocation
  const std::size_t builds_before = sys.neighbors.builds();

  auto write_configuration = [&](const std::string& path, double t, const char* what) {
    const auto masses = sys.species.masses(c.q);
    write_lammps_data(path, sys.particles, sys.box.length(t), masses[0], masses[1],
                      fmt::format("jam {} configuration, dim {} n {} phi {:.17g} seed {}", what, D,
                                  n, sys.box.packing_fraction(t), c.seed));
  };
  // Configurations kept for the jamming point: every output point from --jamming-search-from,
  // by default from the start (the search then leans on nothing but the run itself).
  const double save_from = c.jamming_search_from;
  auto record = [&](double t) {
    if (c.jamming_point && sys.box.packing_fraction(t) >= save_from) {
      SavedConfiguration saved{sys.box.packing_fraction(t), {}};
      for (int d = 0; d < D; ++d) {
        saved.s.insert(saved.s.end(), sys.particles.s[d].begin(), sys.particles.s[d].end());
      }
      st.saved.push_back(std::move(saved));
    }
    st.points.push_back(measure(sys, t, c.rattlers));
    if (!std::isfinite(st.points.back().pressure)) {
      throw std::runtime_error(fmt::format(
          "the dynamics became unstable (non-finite pressure at phi {:.5f}) with --dt {:g}; "
          "reduce --dt",
          st.points.back().packing_fraction, c.dt));
    }
  };

  if (st.phase == RunState<D>::kRelaxing) {
    // A start relaxed by another run of the same sample (another rate) is taken as it is.
    bool from_cache = false;
    if (c.relax && !c.start_cache.empty()) {
      if (auto cached =
              read_checkpoint_or_warn<D>(c.start_cache, relaxation_fingerprint(c), n, true)) {
        sys.particles = std::move(cached->particles);
        sys.neighbors.invalidate();
        stepper.load_state(cached->stepper);
        st.relax_steps = cached->state.relax_steps;
        st.relax_converged = cached->state.relax_converged;
        from_cache = true;
      }
    }
    // Relaxation at zero rate (paper's supplement, "Compression Protocol").
    if (c.relax && !from_cache) {
      const double target_energy = c.resolved_relax_energy();
      sys.box.compression_rate = 0.0;
      while (true) {
        const auto k = st.relax_steps;
        const double t = static_cast<double>(k) * c.dt;
        if (k % 100 == 0) {
          const auto obs = measure(sys, 0.0, false);
          if (!std::isfinite(obs.energy_per_particle)) {
            throw std::runtime_error(fmt::format(
                "relaxation became unstable (non-finite energy) with --dt {:g}; reduce --dt",
                c.dt));
          }
          progress.update_relaxation(obs.energy_per_particle, target_energy, t);
          if (obs.energy_per_particle <= target_energy) {
            st.relax_converged = true;
            break;
          }
          if (t >= c.relax_time_max) break;
        }
        if (k % kStabilityCheckInterval == 0) {
          stability.check(sys, sys.box.length(t), sys.box.packing_fraction(t), "relaxation");
        }
        if (k > 0 && (k & 255) == 0) {
          count_steps(256);
          if (checkpoint_if_due()) {
            summary.interrupted = true;
            return summary;
          }
        }
        stepper.step(sys, t, c.dt);
        ++st.relax_steps;
        ++steps_here;
      }
      sys.box.compression_rate = rate;
      stepper.reset();
      if (!c.start_cache.empty()) {
        write_checkpoint(c.start_cache, relaxation_fingerprint(c), st, sys.particles,
                         stepper.save_state());
      }
    }
    st.phase = RunState<D>::kCompressing;
    if (!c.write_lammps_data.empty()) write_configuration(c.write_lammps_data, 0.0, "initial");
    record(0.0);
  }

  const std::vector<double> targets = output_times(sys.box, meta.phi_init, c.phi_stop, c.phi_step);
  const double t_stop = targets.back();
  const auto n_targets = static_cast<std::int64_t>(targets.size());
  while (st.next_output < n_targets) {
    const auto step = st.steps;
    if (step % kStabilityCheckInterval == 0) {
      const double t_now = static_cast<double>(step) * c.dt;
      stability.check(sys, sys.box.length(t_now), sys.box.packing_fraction(t_now), "compression");
    }
    if (step > 0 && (step & 255) == 0) {
      count_steps(256);
      progress.update(static_cast<double>(step) * c.dt / t_stop,
                      sys.box.packing_fraction(static_cast<double>(step) * c.dt),
                      static_cast<std::size_t>(step), n);
      if (checkpoint_if_due()) {
        summary.interrupted = true;
        return summary;
      }
    }
    // Fixed steps t_k = k dt (never accumulated); the last step is shortened to land on
    // t_stop exactly, and a sliver shorter than 1e-6 dt is folded into it.
    const double t = static_cast<double>(step) * c.dt;
    double h = c.dt;
    double t_after = static_cast<double>(step + 1) * c.dt;
    if (t_stop - t_after < 1e-6 * c.dt) {
      h = t_stop - t;
      t_after = t_stop;
    }
    stepper.step(sys, t, h);
    ++st.steps;
    ++steps_here;
    bool due = false;
    while (st.next_output < n_targets && t_after >= targets[st.next_output]) {
      due = true;
      ++st.next_output;
    }
    if (due) record(t_after);
  }
  count_steps(static_cast<std::size_t>(st.steps % 256));
  stability.check(sys, sys.box.length(t_stop), sys.box.packing_fraction(t_stop), "compression");
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();

  if (c.jamming_point) {
    System<D> scratch(sys.particles, sys.species, sys.box, c.skin);
    scratch.set_threads(c.threads);
    const JammingPoint j = find_jamming_point(scratch, st.saved);
    meta.jamming_packing_fraction = j.packing_fraction;
    meta.jamming_minimizations = j.minimizations;
  }
  meta.steps = st.steps;
  meta.relax_steps = st.relax_steps;
  meta.relax_converged = !c.relax || st.relax_converged;
  if (!c.write_final_lammps_data.empty()) {
    write_configuration(c.write_final_lammps_data, t_stop, "final");
  }
  write_run_file<D>(c.out, c, meta, st.points);
  std::remove(checkpoint_file.c_str());

  summary.steps = static_cast<std::size_t>(st.steps);
  summary.relax_steps = static_cast<std::size_t>(st.relax_steps);
  summary.relax_converged = meta.relax_converged;
  summary.neighbor_builds = sys.neighbors.builds() - builds_before;
  summary.output_points = st.points.size();
  const auto& last = st.points.back();
  summary.final_packing_fraction = last.packing_fraction;
  summary.final_pressure = last.pressure;
  summary.final_contacts_per_particle = last.contacts_per_particle;
  summary.final_energy_per_particle = last.energy_per_particle;
  summary.wall_seconds = wall;
  summary.particle_steps_per_second = wall > 0 ? static_cast<double>(steps_here * n) / wall : 0.0;
  return summary;
}

template <int D>
RunSummary run_dimension(const SimConfig& c, const RunControl& control) {
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
  if (!c.read_lammps_data.empty()) validate_cost(c, meta.n, c.force);  // now that N is known
  SimConfig checked = c;
  checked.n = meta.n;
  validate_box(checked, CompressingBox<D>::length_for_packing(box.particle_volume, c.phi_stop),
               species.max_contact_distance);

  System<D> sys(std::move(start.particles), species, box, c.skin);
  sys.set_threads(c.threads);
  const std::size_t n = sys.size();
  if (meta.integrator == "euler") {
    OverdampedEuler<D> stepper(n);
    return integrate(c, control, sys, stepper, meta);
  }
  if (meta.integrator == "heun") {
    OverdampedHeun<D> stepper(n);
    return integrate(c, control, sys, stepper, meta);
  }
  InertialVerlet<D> stepper(n, c.q);
  return integrate(c, control, sys, stepper, meta);
}

}  // namespace

RunSummary run_compression(const SimConfig& config, const RunControl& control) {
  validate(config);
  // Before anything is allocated: a typo such as --n 2000000000 is refused, not attempted.
  if (config.read_lammps_data.empty()) validate_cost(config, config.n, config.force);
  SimConfig c = config;
  c.out = checked_writable("out", c.out);
  if (!c.write_lammps_data.empty()) {
    c.write_lammps_data = checked_writable("write-lammps-data", c.write_lammps_data);
  }
  if (!c.write_final_lammps_data.empty()) {
    c.write_final_lammps_data =
        checked_writable("write-final-lammps-data", c.write_final_lammps_data);
  }
  return c.dim == 2 ? run_dimension<2>(c, control) : run_dimension<3>(c, control);
}

}  // namespace jam
