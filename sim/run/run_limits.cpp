// Estimates of a run's cost before it starts, and the limits that refuse typos such as
// --dt 1e-300 or --phi-step 1e-12 (declared in sim_config.hpp).
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>

#include "sim/dynamics/integrator_list.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {
namespace {

// A run's memory per particle is measured per integrator and dimension (integrator_list.hpp:
// 103-296 B in 2D, 141-482 B in 3D, one thread); each further thread adds its force scratch,
// measured 36-41 B in 2D and 40-48 B in 3D. The estimate takes 1.25 times the measurements:
// packings denser than the measured starts keep more contacts (+4% at phi 1.0 in 2D, +8% at
// 0.80 in 3D) and the allocator rounds up.
constexpr double kMemoryHeadroom = 1.25;
constexpr double kBytesPerParticlePerExtraThread[2] = {41.0, 48.0};

}  // namespace

RunEstimate estimate_run(const SimConfig& c, std::int64_t n) {
  RunEstimate e;
  const double phi_init = c.read_lammps_data.empty() ? c.phi_init : 0.0;
  // Packing grows as exp(D rate t): the compression lasts ln(phi_stop/phi_init)/(D rate).
  // An adaptive integrator's "steps" are counted as force evaluations at its cost model's
  // near-jamming rate throughout (an upper bound: the plan integrates the packing's factor,
  // integrator_cost.hpp); its steps carry no packing increment to check against the output
  // spacing (dense output, or landing on each point).
  const std::string integrator = c.resolved_integrator();
  const bool adaptive = is_adaptive_integrator(integrator);
  const double per_time =
      adaptive ? force_evaluations_per_time(integrator, c.dim, c.dt, c.compression_rate,
                                            c.resolved_tolerance(), c.rms_error_norm(),
                                            static_cast<double>(n))
               : 1.0 / c.dt;
  if (phi_init > 0) {
    e.compression_steps = std::log(c.phi_stop / phi_init) / (c.dim * c.compression_rate) * per_time;
    e.output_points = (c.phi_stop - phi_init) / c.phi_step + 2;
  } else {
    e.output_points = c.phi_stop / c.phi_step + 2;
  }
  e.relaxation_steps =
      c.relax ? c.relax_time_max *
                    (adaptive ? relaxation_evaluations_per_time(integrator, c.dt) : 1.0 / c.dt)
              : 0.0;
  e.packing_per_step = adaptive ? 0.0 : c.phi_stop * std::expm1(c.dim * c.compression_rate * c.dt);
  // Output points are kept in memory (and in the checkpoint) until the run file is written;
  // with --jamming-point each keeps a configuration too (an upper bound: all of them).
  const double per_point =
      8.0 * (7 + c.dim * c.dim) + (c.jamming_point ? 8.0 * c.dim * static_cast<double>(n) : 0.0);
  const double per_particle = bytes_per_particle(integrator, c.dim) +
                              (c.threads - 1) * kBytesPerParticlePerExtraThread[c.dim == 2 ? 0 : 1];
  e.memory_bytes =
      kMemoryHeadroom * per_particle * static_cast<double>(n) + 2.0 * per_point * e.output_points;
  return e;
}

double memory_limit_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? 0.5 * static_cast<double>(pages) * static_cast<double>(page)
                               : 8.0 * (1ull << 30);
}

void validate_cost(const SimConfig& c, std::int64_t n, bool force) {
  const RunEstimate e = estimate_run(c, n);
  if (!(e.packing_per_step <= c.phi_step)) {
    const double dt_max = std::log1p(c.phi_step / c.phi_stop) / (c.dim * c.compression_rate);
    throw ConfigError(fmt::format(
        "--rate {:g}: one step of --dt {:g} compresses by {:.3g} in packing near phi_stop, more "
        "than --phi-step {:g} between output points; use --dt {:.3g} or less",
        c.compression_rate, c.dt, e.packing_per_step, c.phi_step, dt_max));
  }
  if (force) return;
  const char* how = "; --force runs it anyway";
  if (!(e.output_points <= kMaxOutputPoints)) {
    throw ConfigError(
        fmt::format("--phi-step {:g}: {:.3g} output points, more than the limit {:g}{}", c.phi_step,
                    e.output_points, kMaxOutputPoints, how));
  }
  if (!(e.compression_steps <= kMaxSteps)) {
    throw ConfigError(fmt::format(
        "--dt {:g}: {:.3g} compression steps at --rate {:g}, more than the limit {:g}{}", c.dt,
        e.compression_steps, c.compression_rate, kMaxSteps, how));
  }
  if (!(e.relaxation_steps <= kMaxSteps)) {
    throw ConfigError(fmt::format(
        "--dt {:g}: up to {:.3g} relaxation steps (--relax-time-max {:g}), more than the limit "
        "{:g}{}",
        c.dt, e.relaxation_steps, c.relax_time_max, kMaxSteps, how));
  }
  if (!(e.memory_bytes <= memory_limit_bytes())) {
    throw ConfigError(fmt::format(
        "--n {}: an estimated {:.3g} GB of memory, more than half of this machine's ({:.3g} GB){}",
        n, e.memory_bytes / 1e9, 2 * memory_limit_bytes() / 1e9, how));
  }
}

}  // namespace jam
