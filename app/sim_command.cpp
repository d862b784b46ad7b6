#include "app/sim_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <type_traits>
#include <variant>

#include "sim/io/chain_start.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/run_parameters.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam {

namespace {

/// The option of one table row, bound to its SimConfig member.
CLI::Option* add_parameter(CLI::App& sim, const RunParameter& p, SimConfig& c) {
  return std::visit(
      [&](auto member) {
        auto& target = c.*member;
        using T = std::decay_t<decltype(target)>;
        if constexpr (std::is_same_v<T, bool>) {
          if (p.flag) return sim.add_flag(p.option(), target, p.help);
        }
        return sim.add_option(p.option(), target, p.help);
      },
      p.field);
}

/// CLI11's check of a seed (an unsigned 64-bit member): parse_seed's rules, before the run.
CLI::Validator seed_validator() {
  return CLI::Validator(
      [](std::string& text) {
        try {
          parse_seed("seed", text);
        } catch (const ConfigError&) {
          return text + " is not an integer in [0, 2^63 - 1]";
        }
        return std::string();
      },
      "SEED", "seed");
}

}  // namespace

void add_sim_command(CLI::App& app, SimConfig& c) {
  CLI::App* sim = app.add_subcommand(
      "sim", "Compress one bidisperse soft-sphere packing at a fixed rate and write a run file");
  sim->option_defaults()->always_capture_default();
  for (const RunParameter& p : run_parameters()) {
    CLI::Option* option = add_parameter(*sim, p, c);
    if (std::holds_alternative<std::uint64_t SimConfig::*>(p.field))
      option->check(seed_validator());
    if (!p.choices.empty()) option->type_name(fmt::format("{{{}}}", fmt::join(p.choices, ",")));
  }
  sim->get_option("--out")->required();
  CLI::Option* read = sim->get_option("--read-lammps-data");
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

int run_sim_command(const SimConfig& given) {
  SimConfig c = given;
  if (!c.read_start.empty() && c.start_identity.empty()) {
    // A chained start given by hand: its identity, stored in it, joins this run's.
    try {
      c.start_identity = stored_chain_start_identity(c.read_start);
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("--read-start {}: {}", c.read_start, e.what()));
    }
  }
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
    if (s.resumed) {
      fmt::print("jam sim: resumed from checkpoint (earlier attempts: {:.3g} CPU seconds)\n",
                 s.earlier_cpu_seconds);
    }
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
    fmt::print("  {} force evaluations, {} rejected steps{}\n", s.force_evaluations,
               s.rejected_steps, s.resumed ? " (since the resume)" : "");
    fmt::print("  wrote {}\n", c.out);
  }
  return 0;
}

}  // namespace jam
