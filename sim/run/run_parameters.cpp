#include "sim/run/run_parameters.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <type_traits>

#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/model/contact_laws.hpp"

namespace jam {
namespace {

using C = CampaignKey;
using I = Identity;

ParameterValue resolved_integrator(const SimConfig& c) {
  return c.resolved_integrator();
}

ParameterValue resolved_relax_energy(const SimConfig& c) {
  return c.resolved_relax_energy();
}

// The chained start's identity, shortened to the word a fingerprint carries.
ParameterValue chained_start_key(const SimConfig& c) {
  return c.read_start.empty() ? std::string() : chain_start_key(c.start_identity);
}

ParameterValue resolved_tolerance(const SimConfig& c) {
  return c.resolved_tolerance();
}

ParameterValue relaxation_tolerance(const SimConfig& c) {
  return c.relaxation_tolerance();
}

ParameterValue resolved_transient_tolerance(const SimConfig& c) {
  return c.resolved_transient_tolerance();
}

ParameterValue resolved_dense_output(const SimConfig& c) {
  return c.resolved_dense_output();
}

ParameterValue resolved_stiffest_mode(const SimConfig& c) {
  return c.resolved_stiffest_mode();
}

ParameterValue resolved_error_norm(const SimConfig& c) {
  return c.resolved_error_norm();
}

std::vector<std::string> dynamics_names() {
  return {kDynamics.begin(), kDynamics.end()};
}

// The order of the rows is the order of the fingerprint's words (and of `jam sim --help`):
// never reorder the rows that are fingerprint words, or every stored run changes identity.
std::vector<RunParameter> make_table() {
  return {
      {.name = "dim",
       .field = &SimConfig::dim,
       .help = "Dimension, 2 or 3",
       .campaign = C::required,
       .identity = I::word,
       .relaxation_position = 1,
       .attribute = "dim",
       .choices = {"2", "3"}},
      {.name = "n",
       .field = &SimConfig::n,
       .help = "Number of particles (even; half small d=1, half big)",
       .identity = I::word,
       .relaxation_position = 2,
       .attribute = "n",
       .from_data_file = true},
      {.name = "phi_init",
       .field = &SimConfig::phi_init,
       .help = "Packing fraction of the random start",
       .identity = I::word,
       .relaxation_position = 3,
       .attribute = "phi_init",
       .from_data_file = true},
      {.name = "phi_stop",
       .field = &SimConfig::phi_stop,
       .help = "Packing fraction at which the run ends",
       .campaign = C::required,
       .identity = I::word,
       .attribute = "phi_stop"},
      {.name = "phi_step",
       .field = &SimConfig::phi_step,
       .help = "Output spacing in packing fraction",
       .campaign = C::optional,
       .identity = I::word,
       .attribute = "phi_step"},
      {.name = "rate",
       .field = &SimConfig::compression_rate,
       .help = "Compression rate (true strain rate, 1/t0)",
       .identity = I::word,
       .attribute = "compression_rate",
       .unit = "1/t0"},
      {.name = "dt",
       .field = &SimConfig::dt,
       .help = "Time step (units of t0)",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 5,
       .attribute = "dt",
       .unit = "t0"},
      {.name = "dynamics",
       .field = &SimConfig::dynamics,
       .help = "overdamped (Q -> 0) or inertial",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 6,
       .attribute = "dynamics",
       .choices = dynamics_names()},
      // Allowed values depend on the dynamics: validate() asks the integrator list.
      {.name = "integrator",
       .field = &SimConfig::integrator,
       .help = integrator_help(),
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 7,
       .attribute = "integrator",
       .resolve = resolved_integrator},
      {.name = "q",
       .field = &SimConfig::quality_factor,
       .help = "Quality factor Q (inertial dynamics only)",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 8,
       .attribute = "q",
       .inertial_only = true},
      // A campaign derives each run's seed from its base seed (campaign_file.hpp).
      {.name = "seed",
       .field = &SimConfig::seed,
       .help = "Seed of the random initial configuration, 0 ... 2^63-1",
       .identity = I::word,
       .relaxation_position = 4,
       .attribute = "seed"},
      // The thread count changes the force summation order; campaigns run one
      // single-threaded run per core instead.
      {.name = "threads",
       .field = &SimConfig::threads,
       .help = "Threads of this run; bitwise reproducible for a given count (campaigns run one "
               "single-threaded run per core instead)",
       .identity = I::suffix_unless_default,
       .relaxation_position = 14,
       .attribute = "threads"},
      {.name = "skin",
       .field = &SimConfig::skin,
       .help = "Neighbor-list skin (units of d_s)",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 9,
       .attribute = "skin",
       .unit = "d_s"},
      {.name = "diameter_ratio",
       .field = &SimConfig::diameter_ratio,
       .help = "Big/small diameter ratio",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 10,
       .attribute = "diameter_ratio"},
      {.name = "contact",
       .field = &SimConfig::contact,
       .help = contact_law_help(),
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .relaxation_position = 15,
       .attribute = "contact",
       .choices = contact_law_names()},
      {.name = "tolerance",
       .field = &SimConfig::tolerance,
       .help = "chebyshev integrator: the local error of the displacements allowed in one step "
               "(units of d_s, in the norm of --error-norm); --dt is then its first step. auto = "
               "100 rate within "
               "[1e-4, 3e-3] while compressing ([1e-4, 1e-2] with --dense-output 0; a tenth of it "
               "with --error-norm rms), 1e-4 while relaxing",
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .relaxation_position = 16,
       .attribute = "tolerance",
       .unit = "d_s",
       .resolve = resolved_tolerance,
       .resolve_relaxation = relaxation_tolerance,
       // 1e-4 was the one default before "auto": runs at it keep their identity.
       .unmarked = ParameterValue{kRelaxationTolerance}},
      // Both change only the compression (not the relaxed start); runs from before them, which
      // landed on every output point at one tolerance throughout, keep their identity.
      {.name = "dense_output",
       .field = &SimConfig::dense_output,
       .help = "chebyshev integrator: observables at output points from the continuous "
               "extension of the step (1), or steps cut to land on each output point (0)",
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .attribute = "dense_output",
       .resolve = resolved_dense_output,
       .unmarked = ParameterValue{false}},
      {.name = "transient_tolerance",
       .field = &SimConfig::transient_tolerance,
       .help = "chebyshev integrator: the tolerance until the start's transient is over (the "
               "energy at an output point at or below the relaxation target, or no longer "
               "falling); auto = the relaxation's when tighter than the compression's; off",
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .attribute = "transient_tolerance",
       .unit = "d_s",
       .resolve = resolved_transient_tolerance,
       .unmarked = ParameterValue{0.0}},
      // Changes only the compression, as the two above; runs from before it keep their identity.
      {.name = "stiffest_mode",
       .field = &SimConfig::stiffest_mode,
       .help = "chebyshev integrator: lambda_max, which sets a step's stages, while compressing: "
               "estimate (1.2 times a Lanczos estimate, renewed every 25 steps and after a "
               "rejected step) or bound (the Gershgorin bound, every step)",
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .attribute = "stiffest_mode",
       .choices = {"estimate", "bound"},
       .resolve = resolved_stiffest_mode,
       .unmarked = ParameterValue{std::string("bound")}},
      {.name = "error_norm",
       .field = &SimConfig::error_norm,
       .help = "chebyshev integrator: the norm of a step's local error while compressing: max "
               "(the largest component) or rms (root mean square over the particles)",
       .campaign = C::optional,
       .identity = I::suffix_unless_default,
       .attribute = "error_norm",
       .choices = {"max", "rms"},
       .resolve = resolved_error_norm,
       .unmarked = ParameterValue{std::string("max")}},
      {.name = "relax",
       .field = &SimConfig::relax,
       .help = "Relax the start at zero rate before compressing (the paper's protocol)",
       .campaign = C::optional,
       .identity = I::word,
       .attribute = "relax"},
      {.name = "relax_energy",
       .field = &SimConfig::relax_energy,
       .help = "Relaxation ends when the energy per particle is at or below this; auto = "
               "1e-4 rate^2 (residual pressure ~1% of the rate)",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 11,
       .attribute = "relax_energy",
       .unit = "k_e",
       .resolve = resolved_relax_energy},
      {.name = "relax_time_max",
       .field = &SimConfig::relax_time_max,
       .help = "Longest relaxation (units of t0)",
       .campaign = C::optional,
       .identity = I::word,
       .relaxation_position = 12},
      {.name = "rattlers",
       .field = &SimConfig::rattlers,
       .help = "Also write Z with rattlers removed (fewer than D+1 contacts, iteratively)",
       .campaign = C::optional,
       .identity = I::word,
       .flag = true},
      {.name = "stress",
       .field = &SimConfig::stress,
       .help = "Also write the full stress tensor at each output point",
       .campaign = C::optional,
       .identity = I::word,
       .flag = true},
      {.name = "read_lammps_data",
       .field = &SimConfig::read_lammps_data,
       .help = "Start from this LAMMPS data file (box and packing from the file)",
       .identity = I::word,
       .fingerprint_key = "read",
       .relaxation_position = 13},
      {.name = "jamming_point",
       .field = &SimConfig::jamming_point,
       .help = "Also find the run's jamming point phi_Ji (FIRE minimizations; "
               "docs/statistics-and-checks.md)",
       .campaign = C::optional,
       .identity = I::word,
       .flag = true},
      {.name = "jamming_search_from",
       .field = &SimConfig::jamming_search_from,
       .help = "Lowest packing searched for phi_Ji (0: from the start)",
       .identity = I::word,
       .fingerprint_key = "from"},
      {.name = "out", .field = &SimConfig::out, .help = "Run file to write (HDF5)"},
      {.name = "write_lammps_data",
       .field = &SimConfig::write_lammps_data,
       .help = "Write the configuration the compression starts from as a LAMMPS data file"},
      {.name = "write_final_lammps_data",
       .field = &SimConfig::write_final_lammps_data,
       .help = "Write the configuration at phi-stop as a LAMMPS data file (a start for a "
               "slower rate, as in the paper's protocol)"},
      {.name = "quiet",
       .field = &SimConfig::quiet,
       .help = "No progress display and no summary",
       .flag = true},
      {.name = "force",
       .field = &SimConfig::force,
       .help = "Run even beyond the limits on steps (1e10), output points (1e6) and memory "
               "(half of this machine's) that otherwise refuse the run",
       .flag = true},
      {.name = "checkpoint_interval",
       .field = &SimConfig::checkpoint_interval,
       .help = "Seconds of wall time between checkpoints (<out>.checkpoint); 0 = none. An "
               "interrupted run resumes from its checkpoint when run again",
       .campaign = C::optional},
      // Campaigns with chain_phi_init set these per run (run_plan.cpp).
      {.name = "write_start",
       .field = &SimConfig::write_start,
       .help = "Write a chained start here: the configuration at --write-start-at, from which a "
               "slower run continues (--read-start)"},
      {.name = "write_start_at",
       .field = &SimConfig::write_start_at,
       .help = "Packing of the chained start (the first output point at or after it)"},
      {.name = "read_start",
       .field = &SimConfig::read_start,
       .help = "Continue from a chained start written by a faster run (--write-start), without "
               "relaxing (give --relax 0); its identity is part of this run's",
       .identity = I::suffix_unless_default,
       .fingerprint_key = "start",
       .attribute = "chained_start",
       .resolve = chained_start_key},
  };
}

}  // namespace

std::string RunParameter::option() const {
  std::string o = "--" + name;
  std::replace(o.begin(), o.end(), '_', '-');
  return o;
}

std::string RunParameter::word() const {
  return fingerprint_key.empty() ? name : fingerprint_key;
}

const std::vector<RunParameter>& run_parameters() {
  static const std::vector<RunParameter> table = make_table();
  return table;
}

const RunParameter* find_run_parameter(std::string_view name) {
  for (const auto& p : run_parameters())
    if (p.name == name) return &p;
  return nullptr;
}

ParameterValue field_value(const SimConfig& c, const RunParameter& p) {
  return std::visit(
      [&c](auto member) -> ParameterValue {
        const auto& v = c.*member;
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, int>) {
          return std::int64_t{v};
        } else {
          return v;
        }
      },
      p.field);
}

ParameterValue zero_like(const ParameterValue& v) {
  return std::visit([](const auto& x) -> ParameterValue { return std::decay_t<decltype(x)>{}; }, v);
}

namespace {

/// A value as stored: 0 for an inertial-only parameter of an overdamped run.
ParameterValue as_stored(const SimConfig& c, const RunParameter& p, ParameterValue v) {
  return p.inertial_only && c.dynamics != "inertial" ? zero_like(v) : v;
}

}  // namespace

ParameterValue stored_value(const SimConfig& c, const RunParameter& p) {
  return as_stored(c, p, p.resolve ? p.resolve(c) : field_value(c, p));
}

ParameterValue stored_relaxation_value(const SimConfig& c, const RunParameter& p) {
  return p.resolve_relaxation ? as_stored(c, p, p.resolve_relaxation(c)) : stored_value(c, p);
}

std::string fingerprint_text(const ParameterValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>) {
          return fmt::format("{:.17g}", x);
        } else {
          return fmt::format("{}", x);
        }
      },
      v);
}

std::string message_text(const ParameterValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>) {
          return fmt::format("{:g}", x);
        } else {
          return fmt::format("{}", x);
        }
      },
      v);
}

}  // namespace jam
