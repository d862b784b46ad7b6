#pragma once
// One compression run in its phases (resume, relax, compress, finish), on a system, an
// integrator and a contact law already chosen; compression_run.cpp sets them up from the
// configuration and is the only user.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "sim/dynamics/integrators.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/run_file.hpp"
#include "sim/observables/jamming_point.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/checkpointer.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/output_grid.hpp"
#include "sim/run/output_recorder.hpp"
#include "sim/run/progress.hpp"
#include "sim/run/run_inputs.hpp"
#include "sim/run/run_state.hpp"
#include "sim/run/stability_guard.hpp"
#include "sim/run/start_transient.hpp"

namespace jam::detail {

/// One compression run in named phases: resume (from the run's checkpoint), relax (at zero
/// rate, or from the sample's cached relaxed start), compress (to phi_stop, recording output
/// points), finish (jamming point, run file). The box is at rest during relaxation and starts
/// compressing, once, when the compression phase begins; nothing is changed and then restored.
template <int D, class Contact, class Stepper>
class CompressionRun {
 public:
  using Clock = std::chrono::steady_clock;
  // Adaptive integrators choose their own steps (times accumulate in RunState); the others
  // take fixed steps t_k = k dt.
  static constexpr bool kAdaptive = is_adaptive<Stepper>();

  CompressionRun(const SimConfig& c, const RunControl& control, System<D, Contact>& sys,
                 Stepper& stepper, const CompressingBox<D>& compressing_box, RunMetadata meta)
      : c_(c),
        control_(control),
        sys_(sys),
        stepper_(stepper),
        compressing_box_(compressing_box),
        meta_(std::move(meta)),
        checkpointer_(c.out, fingerprint(c), control),
        recorder_(c),
        stability_(c, sys.species),
        progress_(!c.quiet, c.phi_stop),
        wall_start_(Clock::now()),
        builds_before_(sys.neighbors.builds()) {
    sys_.guard_rebuilds = !kAdaptive;
  }

  RunSummary run() {
    summary_.resumed = resume();
    summary_.n = sys_.size();
    summary_.phi_init = meta_.phi_init;
    summary_.initial_box_length = meta_.initial_box_length;
    if (st_.phase == RunState<D>::kRelaxing) {
      if (!relax()) return interrupted();
      begin_compression();
    } else {
      sys_.box = compressing_box_;  // resumed in the compression phase
    }
    // Error control at the compression's tolerance ("auto": rate-dependent, sim_config.hpp),
    // at the transient's while the start's transient lasts (start_transient.hpp).
    if constexpr (kAdaptive) {
      in_transient_ = c_.resolved_transient_tolerance() > 0.0 &&
                      !start_transient_over(st_.points, c_.resolved_relax_energy());
      stepper_.set_tolerance(in_transient_ ? c_.resolved_transient_tolerance()
                                           : c_.resolved_tolerance());
      stepper_.set_stiffest_mode_estimate(c_.resolved_stiffest_mode() == "estimate");
      stepper_.set_error_norm_rms(c_.rms_error_norm());
    }
    if (!compress()) return interrupted();
    if (control_.start_only) return start_written();
    return finish();
  }

 private:
  /// Continues from the run's own checkpoint when there is a trustworthy one.
  bool resume() {
    auto saved = checkpointer_.read(sys_.size());
    if (!saved) return false;
    // Past the start's packing a checkpoint can no longer give the start: begin afresh.
    if (control_.start_only && !saved->state.points.empty() &&
        saved->state.points.back().packing_fraction >= start_target()) {
      return false;
    }
    sys_.particles = std::move(saved->particles);
    sys_.neighbors.invalidate();
    stepper_.load_state(saved->stepper);
    st_ = std::move(saved->state);
    checkpointer_.resumed_after(st_.cpu_seconds);
    summary_.earlier_cpu_seconds = st_.cpu_seconds;
    // An adaptive stepper recomputes the first slope of its next step, which the uninterrupted
    // run carried over: not counted, so that a resumed run's file is the same.
    evaluations_redone_ = kAdaptive && st_.phase == RunState<D>::kCompressing ? 1 : 0;
    return true;
  }

  /// Relaxation at zero rate (paper's supplement, "Compression Protocol"), or the relaxed start
  /// another rate of the same sample left in the start cache. False: stopped on request.
  bool relax() {
    if (!c_.relax) return true;
    if (!c_.start_cache.empty()) {
      if (auto cached = read_checkpoint_or_warn<D>(c_.start_cache, relaxation_fingerprint(c_),
                                                   sys_.size(), true)) {
        sys_.particles = std::move(cached->particles);
        sys_.neighbors.invalidate();
        stepper_.load_state(cached->stepper);
        st_.relax_steps = cached->state.relax_steps;
        st_.relax_converged = cached->state.relax_converged;
        return true;
      }
    }
    const double target_energy = c_.resolved_relax_energy();
    while (true) {
      const auto k = st_.relax_steps;
      const double t = kAdaptive ? st_.relax_time : static_cast<double>(k) * c_.dt;
      if (k % 100 == 0) {
        const auto obs = measure(sys_, 0.0, false);
        if (!std::isfinite(obs.energy_per_particle)) {
          throw std::runtime_error(fmt::format(
              "relaxation became unstable (non-finite energy) with --dt {:g}; reduce --dt", c_.dt));
        }
        progress_.update_relaxation(obs.energy_per_particle, target_energy, t);
        if (obs.energy_per_particle <= target_energy) {
          st_.relax_converged = true;
          break;
        }
        if (t >= c_.relax_time_max) break;
      }
      if (!kAdaptive && k % kStabilityCheckInterval == 0) {
        stability_.check(sys_, sys_.box.length(t), sys_.box.packing_fraction(t), "relaxation");
      }
      if (k > 0 && (k & 255) == 0 && pause_due()) return false;
      if (stop_now()) return pause_at_once();
      if constexpr (kAdaptive) {
        st_.relax_time += stepper_.step(sys_, t, std::numeric_limits<double>::infinity());
      } else {
        stepper_.step(sys_, t, c_.dt);
      }
      ++st_.relax_steps;
      ++steps_here_;
    }
    stepper_.reset();
    if (!c_.start_cache.empty()) {
      write_checkpoint(c_.start_cache, relaxation_fingerprint(c_), st_, sys_.particles,
                       stepper_.save_state());
    }
    return true;
  }

  /// The start of the compression: its first output point, t = 0.
  void begin_compression() {
    sys_.box = compressing_box_;
    st_.phase = RunState<D>::kCompressing;
    if (!c_.write_lammps_data.empty()) write_configuration(c_.write_lammps_data, 0.0, "initial");
    recorder_.record(sys_, st_, 0.0);
  }

  /// Compression at the rate to phi_stop, with output points at each target time: from the
  /// continuous extension of the step that passes it (dense output), or at the end of the
  /// step that reaches it (steps cut to land on it; fixed steps: the first at or after it).
  /// False: stopped on request.
  bool compress() {
    const std::vector<double> targets =
        output_times(sys_.box, meta_.phi_init, c_.phi_stop, c_.phi_step);
    t_stop_ = targets.back();
    const auto n_targets = static_cast<std::int64_t>(targets.size());
    const bool dense = kAdaptive && c_.resolved_dense_output();
    evaluations_mark_ = sys_.force_evaluations();
    while (st_.next_output < n_targets) {
      const auto step = st_.steps;
      const double t = kAdaptive ? st_.time : static_cast<double>(step) * c_.dt;
      if (!kAdaptive && step % kStabilityCheckInterval == 0) {
        stability_.check(sys_, sys_.box.length(t), sys_.box.packing_fraction(t), "compression");
      }
      if (step > 0 && (step & 255) == 0) {
        progress_.update(t / t_stop_, sys_.box.packing_fraction(t), static_cast<std::size_t>(step),
                         sys_.size());
        if (pause_due()) return false;
      }
      if (stop_now()) return pause_at_once();
      // Dense output lands only on phi_stop, whose configuration ends the run.
      const double limit = dense ? t_stop_ : targets[st_.next_output];
      const double t_after = advance(t, limit);
      ++st_.steps;
      ++steps_here_;
      bool due = false;
      while (st_.next_output < n_targets && t_after >= targets[st_.next_output]) {
        if (dense && targets[st_.next_output] < t_after) {
          record_interpolated(targets[st_.next_output]);
        } else {
          due = true;
        }
        ++st_.next_output;
      }
      if (due) {
        recorder_.record(sys_, st_, t_after);
        leave_chain_start(t_after);
      }
      if (control_.start_only && start_written_) break;
      if constexpr (kAdaptive) leave_transient_when_over();
    }
    count_work();
    if (!kAdaptive && !(control_.start_only && start_written_)) {
      stability_.check(sys_, sys_.box.length(t_stop_), sys_.box.packing_fraction(t_stop_),
                       "compression");
    }
    progress_.finish();
    return true;
  }

  /// The output point at time t inside the step just taken, from its continuous extension:
  /// the interpolated positions stand in for the particles while the recorder measures them
  /// (one force evaluation) and a chained start is taken from them, and the step's own end is
  /// put back.
  void record_interpolated(double t) {
    if constexpr (kAdaptive) {
      stepper_.interpolate(t, between_);
      std::swap(sys_.particles.s, between_);
      recorder_.record(sys_, st_, t);
      leave_chain_start(t);
      std::swap(sys_.particles.s, between_);
    }
  }

  /// From the transient's tolerance to the compression's, once, when the recorded points say
  /// the start's transient is over.
  void leave_transient_when_over() {
    if (!in_transient_ || st_.points.size() == transient_checked_) return;
    transient_checked_ = st_.points.size();
    if (!start_transient_over(st_.points, c_.resolved_relax_energy())) return;
    in_transient_ = false;
    stepper_.set_tolerance(c_.resolved_tolerance());
  }

  /// At the first output point at or after --write-start-at (never again on resuming past it):
  /// the configuration a slower run of the sample continues from (chain_start.hpp).
  void leave_chain_start(double t) {
    if (c_.write_start.empty() || st_.points.size() < 2 || start_written_) return;
    const double target = start_target();
    const double before = st_.points[st_.points.size() - 2].packing_fraction;
    const double now = st_.points.back().packing_fraction;
    if (!(before < target && now >= target)) return;
    ChainStart<D> start{sys_.particles, sys_.box.length(t), now,
                        chain_start_identity(fingerprint(c_), c_.write_start_at)};
    write_chain_start(c_.write_start, start);
    start_written_ = true;
  }

  /// The packing at or after which the first output point leaves the chained start.
  double start_target() const { return c_.write_start_at * (1.0 - 1e-12); }

  /// The end of a run asked for its chained start only (RunControl::start_only): no run file.
  RunSummary start_written() {
    if (!start_written_) {
      throw ConfigError(fmt::format("write-start-at {:g}: the run passed no output point there",
                                    c_.write_start_at));
    }
    checkpointer_.remove();
    summary_.start_only = true;
    summary_.steps = static_cast<std::size_t>(st_.steps);
    summary_.output_points = st_.points.size();
    summary_.final_packing_fraction = st_.points.back().packing_fraction;
    summary_.wall_seconds = std::chrono::duration<double>(Clock::now() - wall_start_).count();
    return summary_;
  }

  /// One step of the compression from t towards the next output time; returns the time
  /// reached. Fixed steps land on t_{k+1} = (k + 1) dt (never accumulated; the last step is
  /// shortened to land on t_stop exactly, and a sliver shorter than 1e-6 dt is folded into it).
  /// Adaptive steps accumulate and land exactly on each output time.
  double advance(double t, double next_target) {
    if constexpr (kAdaptive) {
      const double h = stepper_.step(sys_, t, next_target - t);
      st_.time = h == next_target - t ? next_target : t + h;
      return st_.time;
    } else {
      double h = c_.dt;
      double t_after = static_cast<double>(st_.steps + 1) * c_.dt;
      if (t_stop_ - t_after < 1e-6 * c_.dt) {
        h = t_stop_ - t;
        t_after = t_stop_;
      }
      stepper_.step(sys_, t, h);
      return t_after;
    }
  }

  /// The jamming point (FIRE on a scratch copy), the run file, and the summary.
  RunSummary finish() {
    const double wall = std::chrono::duration<double>(Clock::now() - wall_start_).count();
    // The compression's count complete before the search, whose checkpoints hold it (the
    // search minimizes a scratch copy and adds none).
    tally_evaluations();
    if (c_.jamming_point) {
      System<D, Contact> scratch(sys_.particles, sys_.species, sys_.box, c_.skin);
      scratch.set_threads(c_.threads);
      // A checkpoint when one is due after each decision, so that a run killed mid-search
      // (SIGKILL, a lost machine) keeps the decisions made before its last checkpoint.
      // Its minimizations count in the progress after each decision.
      std::uint64_t searched = scratch.force_evaluations();
      const JammingPoint j =
          find_jamming_point(scratch, st_.saved, control_.stop, &st_.jamming_answers, [&] {
            add_work(scratch.force_evaluations() - searched);
            searched = scratch.force_evaluations();
            checkpointer_.checkpoint_if_due(st_, sys_.particles, stepper_.save_state());
          });
      if (j.stopped) {
        // The compression is done and its state (saved configurations and the search's
        // decisions so far included) goes into the checkpoint; resuming replays the decisions
        // and minimizes only from the one that stopped.
        pause_at_once();
        return interrupted();
      }
      meta_.jamming_packing_fraction = j.packing_fraction;
      meta_.jamming_minimizations = j.minimizations;
    }
    meta_.steps = st_.steps;
    meta_.force_evaluations = st_.force_evaluations;
    meta_.relax_steps = st_.relax_steps;
    meta_.relax_converged = !c_.relax || st_.relax_converged;
    if (!c_.write_final_lammps_data.empty()) {
      write_configuration(c_.write_final_lammps_data, t_stop_, "final");
    }
    write_run_file<D>(c_.out, c_, meta_, st_.points);
    checkpointer_.remove();

    summary_.steps = static_cast<std::size_t>(st_.steps);
    summary_.relax_steps = static_cast<std::size_t>(st_.relax_steps);
    summary_.relax_converged = meta_.relax_converged;
    summary_.neighbor_builds = sys_.neighbors.builds() - builds_before_;
    summary_.force_evaluations = sys_.force_evaluations();
    if constexpr (kAdaptive) summary_.rejected_steps = stepper_.stats().rejections;
    summary_.output_points = st_.points.size();
    const auto& last = st_.points.back();
    summary_.final_packing_fraction = last.packing_fraction;
    summary_.final_pressure = last.pressure;
    summary_.final_contacts_per_particle = last.contacts_per_particle;
    summary_.final_energy_per_particle = last.energy_per_particle;
    summary_.wall_seconds = wall;
    summary_.particle_steps_per_second =
        wall > 0 ? static_cast<double>(steps_here_ * sys_.size()) / wall : 0.0;
    return summary_;
  }

  /// Every 256 steps: counts the work for the campaign's progress and takes a checkpoint when
  /// due.
  /// True when the run must stop (a checkpoint then holds its state).
  bool pause_due() {
    count_work();
    tally_evaluations();
    return checkpointer_.checkpoint_if_due(st_, sys_.particles, stepper_.save_state());
  }

  /// A stop asked for between the checks every 256 steps: a large run takes seconds for 256
  /// steps, and SIGTERM must end it within a second (a checkpoint holds the state). One atomic
  /// load per step.
  bool stop_now() const { return control_.stop && control_.stop->load(std::memory_order_relaxed); }

  /// Stops now, with a checkpoint. Always false (stopped).
  bool pause_at_once() {
    count_work();
    tally_evaluations();
    checkpointer_.checkpoint_if_due(st_, sys_.particles, stepper_.save_state());
    return false;
  }

  /// The compression's force evaluations since the last tally into the run state.
  void tally_evaluations() {
    if (st_.phase != RunState<D>::kCompressing) return;
    const std::uint64_t now = sys_.force_evaluations();
    if (now == evaluations_mark_) return;
    st_.force_evaluations +=
        static_cast<std::int64_t>(now - evaluations_mark_ - evaluations_redone_);
    evaluations_mark_ = now;
    evaluations_redone_ = 0;
  }

  /// The force evaluations since the last count (relaxation and compression) times N, into
  /// the campaign's progress: the unit the planner estimates a run in (campaign/run_plan.cpp),
  /// so that its ETA is right before the first run finishes. Steps were counted before, which
  /// the Chebyshev integrator takes about 17 times fewer of than evaluations.
  void count_work() {
    const std::uint64_t now = sys_.force_evaluations();
    add_work(now - counted_mark_);
    counted_mark_ = now;
  }

  void add_work(std::uint64_t evaluations) {
    const std::uint64_t particle_steps = evaluations * sys_.size();
    summary_.counted_particle_steps += particle_steps;
    if (control_.particle_steps) control_.particle_steps->fetch_add(particle_steps);
  }

  RunSummary interrupted() {
    summary_.interrupted = true;
    return summary_;
  }

  void write_configuration(const std::string& path, double t, const char* what) const {
    const auto masses = sys_.species.masses(c_.quality_factor);
    write_lammps_data(path, sys_.particles, sys_.box.length(t), masses[0], masses[1],
                      fmt::format("jam {} configuration, dim {} n {} phi {:.17g} seed {}", what, D,
                                  sys_.size(), sys_.box.packing_fraction(t), c_.seed));
  }

  const SimConfig& c_;
  const RunControl& control_;
  System<D, Contact>& sys_;
  Stepper& stepper_;
  CompressingBox<D> compressing_box_;
  RunMetadata meta_;
  Checkpointer<D> checkpointer_;
  OutputRecorder recorder_;
  StabilityGuard<D> stability_;
  Progress progress_;
  RunState<D> st_;
  RunSummary summary_;
  Clock::time_point wall_start_;
  std::size_t builds_before_;
  std::uint64_t evaluations_mark_ = 0;    // sys_.force_evaluations() at the last tally
  std::uint64_t counted_mark_ = 0;        // ... at the last count_work()
  std::uint64_t evaluations_redone_ = 0;  // of those since, not the run's own (resume())
  std::size_t steps_here_ = 0;  // relaxation and compression steps done by this invocation
  double t_stop_ = 0.0;
  bool in_transient_ = false;                   // at the transient tolerance (adaptive)
  bool start_written_ = false;                  // the chained start left by this invocation
  std::size_t transient_checked_ = 0;           // points seen by leave_transient_when_over
  std::array<std::vector<double>, D> between_;  // positions inside a step (dense output)
};

}  // namespace jam::detail
