#include "app/sim_command.hpp"

#include <fmt/format.h>

#include "sim/run/compression_run.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam {

void add_sim_command(CLI::App& app, SimConfig& c) {
  CLI::App* sim = app.add_subcommand(
      "sim", "Compress one bidisperse soft-sphere packing at a fixed rate and write a run file");
  sim->option_defaults()->always_capture_default();
  sim->add_option("--dim", c.dim, "Dimension, 2 or 3");
  sim->add_option("--n", c.n, "Number of particles (even; half small d=1, half big)");
  sim->add_option("--phi-init", c.phi_init, "Packing fraction of the random start");
  sim->add_option("--phi-stop", c.phi_stop, "Packing fraction at which the run ends");
  sim->add_option("--phi-step", c.phi_step, "Output spacing in packing fraction");
  sim->add_option("--rate", c.compression_rate, "Compression rate (true strain rate, 1/t0)");
  sim->add_option("--dt", c.dt, "Time step (units of t0)");
  sim->add_option("--dynamics", c.dynamics, "overdamped (Q -> 0) or inertial");
  sim->add_option("--integrator", c.integrator,
                  "euler or heun (overdamped; default heun), verlet (inertial)");
  sim->add_option("--tolerance", c.tolerance,
                  "chebyshev: largest local error of a particle's displacement per step (d_s)");
  sim->add_option("--contact", c.contact, "Contact law: harmonic or hertzian");
  sim->add_option("--q", c.q, "Quality factor Q (inertial dynamics only)");
  sim->add_option("--seed", c.seed, "Seed of the random initial configuration, 0 ... 2^63-1")
      ->check(CLI::Validator(
          [](std::string& text) {
            try {
              parse_seed("seed", text);
            } catch (const ConfigError&) {
              return text + " is not an integer in [0, 2^63 - 1]";
            }
            return std::string();
          },
          "SEED", "seed"));
  sim->add_option("--threads", c.threads,
                  "Threads of this run; bitwise reproducible for a given count (campaigns run one "
                  "single-threaded run per core instead)");
  sim->add_option("--skin", c.skin, "Neighbor-list skin (units of d_s)");
  sim->add_option("--diameter-ratio", c.diameter_ratio, "Big/small diameter ratio");
  sim->add_option("--relax", c.relax,
                  "Relax the start at zero rate before compressing (the paper's protocol)");
  sim->add_option("--relax-energy", c.relax_energy,
                  "Relaxation ends when the energy per particle is at or below this; auto = "
                  "1e-4 rate^2 (residual pressure ~1% of the rate)");
  sim->add_option("--relax-time-max", c.relax_time_max, "Longest relaxation (units of t0)");
  sim->add_flag("--stress", c.stress, "Also write the full stress tensor at each output point");
  sim->add_flag("--jamming-point", c.jamming_point,
                "Also find the run's jamming point phi_Ji (FIRE minimizations; "
                "docs/statistics-and-checks.md)");
  sim->add_option("--jamming-search-from", c.jamming_search_from,
                  "Lowest packing searched for phi_Ji (0: from the start)");
  sim->add_flag("--rattlers", c.rattlers,
                "Also write Z with rattlers removed (fewer than D+1 contacts, iteratively)");
  sim->add_option("--out", c.out, "Run file to write (HDF5)")->required();
  auto* read = sim->add_option("--read-lammps-data", c.read_lammps_data,
                               "Start from this LAMMPS data file (box and packing from the file)");
  sim->add_option("--write-lammps-data", c.write_lammps_data,
                  "Write the configuration the compression starts from as a LAMMPS data file");
  sim->add_option("--write-final-lammps-data", c.write_final_lammps_data,
                  "Write the configuration at phi-stop as a LAMMPS data file (a start for a "
                  "slower rate, as in the paper's protocol)");
  sim->add_flag("--quiet", c.quiet, "No progress display and no summary");
  sim->add_flag("--force", c.force,
                "Run even beyond the limits on steps (1e10), output points (1e6) and memory "
                "(half of this machine's) that otherwise refuse the run");
  sim->add_option("--checkpoint-interval", c.checkpoint_interval,
                  "Seconds of wall time between checkpoints (<out>.checkpoint); 0 = none. An "
                  "interrupted run resumes from its checkpoint when run again");
  sim->callback([sim, read, &c]() {
    c.n_given = sim->count("--n") > 0;
    c.phi_init_given = sim->count("--phi-init") > 0;
    if (read->count() == 0) {
      c.n_given = c.phi_init_given = true;  // defaults apply to generated configurations
    }
  });
}

namespace {
std::atomic<bool> stop_requested{false};
extern "C" void request_stop(int) {
  stop_requested.store(true);
}
}  // namespace

int run_sim_command(const SimConfig& c) {
  // Ctrl-C or SIGTERM: write a checkpoint and stop; the same command resumes.
  RunControl control;
  control.checkpoint_interval_seconds = c.checkpoint_interval;
  control.stop = &install_stop_handlers();
  const RunSummary s = run_compression(c, control);
  if (s.interrupted) {
    fmt::print(stderr, "jam: interrupted; state saved in {}; run the same command to resume\n",
               c.out + ".checkpoint");
    return 130;
  }
  if (!c.quiet) {
    if (s.resumed) fmt::print("jam sim: resumed from checkpoint\n");
    fmt::print("jam sim: {}D, N = {}, rate {:g}, {} dt {:g}\n", c.dim, s.n, c.compression_rate,
               c.resolved_integrator(), c.dt);
    fmt::print("  phi {:.6f} -> {:.6f} in {} steps ({} relaxation steps{}), {} output points\n",
               s.phi_init, s.final_packing_fraction, s.steps, s.relax_steps,
               s.relax_converged ? "" : ", NOT converged", s.output_points);
    fmt::print("  at phi_stop: pressure {:.6e}, Z {:.4f}, energy/particle {:.6e}\n",
               s.final_pressure, s.final_contacts_per_particle, s.final_energy_per_particle);
    fmt::print("  bulk viscosity p/rate {:.6e}\n", s.final_pressure / c.compression_rate);
    fmt::print("  wall time {:.2f} s, {:.3g} particle-steps/s, {} neighbor-list builds\n",
               s.wall_seconds, s.particle_steps_per_second, s.neighbor_builds);
    fmt::print("  {} force evaluations{}\n", s.force_evaluations,
               s.rejected_steps ? fmt::format(", {} steps rejected and retried", s.rejected_steps)
                                : std::string());
    fmt::print("  wrote {}\n", c.out);
  }
  return 0;
}

}  // namespace jam
