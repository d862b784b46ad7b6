#pragma once
// Parameters of one compression run (`jam sim`), their defaults and their validation. How each
// is named, fingerprinted and stored: the table in run_parameters.hpp.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "sim/dynamics/integrator_cost.hpp"

namespace jam {

/// Bad input: the message names the option and its value, in one line.
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The Chebyshev integrator's default tolerance at compression rate `rate`: 100 rate within
/// [1e-4, 3e-3] (dense output), or within [1e-4, 1e-2] when its steps land on every output
/// point. Below jamming the pressure a compression builds is zeta rate, so a displacement error
/// that is harmless at fast rates is not at slow ones. Measured (docs/performance.md, the
/// Chebyshev integrator and dense output): landed, the ensemble-mean pressure within 5.5e-5 of
/// a converged reference at 1e-3 and 1e-4 (tolerance 1e-2), 2.4e-5 at 1e-5 (1e-3), 2.3e-4 at
/// 1e-6 (1e-4); 1e-2 at 1e-6 left 5.6e-3. Landing capped the fast rates' steps at the output
/// spacing; free of the grid, 1e-2 left 0.1% (one start) to 0.4% (four, against LAMMPS) in 3D
/// at rate 1e-3 where the pressure is still small (phi 0.61), 3e-3 0.06%.
/// With the root-mean-square norm (error_norm "rms") a tenth of it (kRmsToleranceRatio,
/// integrator_cost.hpp).
inline double auto_tolerance(double rate, bool dense_output = true, bool rms = false) {
  return std::clamp(100.0 * rate, 1e-4, dense_output ? 3e-3 : 1e-2) *
         (rms ? kRmsToleranceRatio : 1.0);
}
/// ... and of the relaxation at zero rate, whatever the rate that follows, so that one relaxed
/// start serves every rate of a sample: 1e-4, the tolerance of the slowest rates.
inline constexpr double kRelaxationTolerance = 1e-4;

struct SimConfig {
  int dim = 2;
  std::int64_t n = 1024;
  double phi_init = 0.6;
  double phi_stop = 0.86;
  double phi_step = 0.001;
  double compression_rate = 1e-4;
  // Overdamped default: Heun at dt = 0.1 (docs/performance.md, the defaults: pressure error below
  // 3e-6 at rates 1e-3 to 1e-5, 2.5-4x less work than Euler at dt = 0.01 and 100x more
  // accurate; the stiffest contact mode, lambda_max = 5-10 from phi = 0.45 to 0.95, allows
  // dt up to about 0.2). Inertial dynamics needs dt below 4 Q^2 / D: give it explicitly.
  double dt = 0.1;
  std::string dynamics = "overdamped";  // overdamped | inertial
  std::string integrator;               // empty: the dynamics' default (integrator_list.hpp)
  // chebyshev: the local error of the displacements allowed in one step (d_s; error_norm);
  // --dt is then its first step. "auto": the compression at auto_tolerance(rate), the
  // relaxation at kRelaxationTolerance (see below).
  std::string tolerance = "auto";
  // chebyshev: observables at output points from the continuous extension of the step that
  // passes them (one force evaluation there), so that the output grid does not cut the steps;
  // 0: steps cut to land on every output point (the behaviour of runs before it existed).
  bool dense_output = true;
  // chebyshev: the tolerance while the start's transient lasts, i.e. from the start of the
  // compression until the energy per particle at an output point is at or below the
  // relaxation target or no longer falls (start_transient.hpp). "auto": the relaxation's
  // tolerance when it is tighter than the compression's (an unrelaxed start's violent
  // transient integrated at 1e-2 left 1.3% in the pressure at rate 1e-4); "off": none.
  std::string transient_tolerance = "auto";
  // chebyshev: lambda_max, which sets the stages of a step, while compressing: "estimate" (1.2
  // times a Lanczos estimate renewed every 25 steps and after a rejected step) or "bound" (the
  // Gershgorin bound every step, the behaviour of runs before the estimate existed; about twice
  // lambda_max on jammed packings: docs/performance.md, "The stiffest mode").
  std::string stiffest_mode = "estimate";
  // chebyshev: the norm of the step's local error while compressing: "max" (the largest
  // component) or "rms" (root mean square over the particles, as in the RKC code; with the
  // largest, every rearrangement anywhere in the box shortens the step, so that steps shorten as
  // N grows: docs/performance.md, "The error norm", measures both).
  std::string error_norm = "max";
  double quality_factor = 0.03;  // Q, inertial dynamics only (run parameter "q")
  std::uint64_t seed = 1;
  double skin = 0.3;
  // Threads of this one run (a campaign runs one single-threaded run per core instead). The
  // numbers are bitwise the same for the same thread count; with another count they agree to
  // round-off, then drift apart chaotically (sim/parallel.hpp).
  int threads = 1;
  double diameter_ratio = 1.4;
  // The contact law: harmonic (the paper's) or hertzian. Fingerprints name it only when it is
  // not harmonic, so that the harmonic runs keep the identity they had before it existed.
  std::string contact = "harmonic";
  bool relax = true;  // relax the start at zero rate (paper's protocol)
  // ... until the energy per particle is at or below this; "auto" = 1e-4 rate^2, so that the
  // residual pressure of the start (~ sqrt(E)) is ~1% of rate, well below the pressure the
  // compression itself builds (zeta rate, with bulk viscosity zeta >= 1 at any phi).
  std::string relax_energy = "auto";
  double relax_time_max = 1e4;  // ... or this much time has passed
  bool stress = false;
  bool rattlers = false;
  bool jamming_point =
      false;  // find phi_Ji (FIRE minimizations, see observables/jamming_point.hpp)
  double jamming_search_from = 0.0;  // lowest packing searched; 0: from the start
  std::string out;
  // Chained starts (sim/io/chain_start.hpp): this run writes the configuration of its first
  // output point at or after write_start_at to write_start; a run reads one with read_start
  // and continues from it without relaxing. start_identity: the identity the start must carry
  // (campaigns know it in advance; `jam sim` takes it from the file).
  std::string write_start;
  double write_start_at = 0.0;
  std::string read_start;
  std::string start_identity;
  std::string read_lammps_data;
  std::string write_lammps_data;
  std::string write_final_lammps_data;
  bool quiet = false;
  bool force = false;  // run beyond the limits of validate_cost (not part of the physics)
  // Where the run belongs, written into the run file (not part of the physics): the campaign's
  // name and the run's sample number there (-1: a single run).
  std::string campaign;
  std::int64_t sample = -1;
  double checkpoint_interval = 300.0;  // seconds of wall time; 0: none (not part of the physics)
  // Relaxed-start cache (campaigns): the state right after relaxation, shared by every rate of
  // a sample. Read when it exists, written when this run relaxes. Results are bitwise the same
  // with or without it; it only saves repeating the relaxation.
  std::string start_cache;

  bool phi_init_given = true;  // false when taken from --read-lammps-data
  bool n_given = true;

  /// The relaxation target after resolving "auto" (throws ConfigError when malformed).
  double resolved_relax_energy() const;

  /// The compression's tolerance after resolving "auto" (throws ConfigError when malformed);
  /// for integrators without error control, which ignore it, kRelaxationTolerance.
  double resolved_tolerance() const;
  /// The relaxation's tolerance after resolving "auto".
  double relaxation_tolerance() const;
  /// The tolerance during the start's transient after resolving "auto"/"off"; 0: none (the
  /// compression's tolerance throughout, as for integrators without error control).
  double resolved_transient_tolerance() const;
  /// Whether output points come from the continuous extension (adaptive integrators only).
  bool resolved_dense_output() const;
  /// "estimate" or "bound" for adaptive integrators; "bound" (unused) for the others.
  std::string resolved_stiffest_mode() const;
  /// "rms" or "max" for adaptive integrators; "max" (unused) for the others.
  std::string resolved_error_norm() const;
  /// Whether the resolved error norm is the root mean square ("rms").
  bool rms_error_norm() const { return resolved_error_norm() == "rms"; }

  /// The integrator after applying the dynamics-dependent default.
  std::string resolved_integrator() const {
    if (!integrator.empty()) return integrator;
    return std::string(
        default_integrator(dynamics == "inertial" ? "inertial" : "overdamped", compression_rate));
  }
};

/// Seeds lie in [0, kMaxSeed] = [0, 2^63 - 1], so that each is stored exactly in the run
/// file's int64 attribute "seed" and two different seeds never store the same number.
constexpr std::uint64_t kMaxSeed = (std::uint64_t{1} << 63) - 1;

/// A seed given as text (decimal digits only, at most kMaxSeed); throws ConfigError naming
/// `option` and the text otherwise. Negative, fractional and overflowing values are refused
/// rather than wrapped.
std::uint64_t parse_seed(const std::string& option, const std::string& text);

/// The inertial model's quality factor Q is meaningful in the strongly overdamped regime the
/// paper works in (Q = 0.01 in 2D, 0.0225 in 3D, "Q < 1"): --q must lie in (0, 1].
constexpr double kMaxQualityFactor = 1.0;

/// Checks every parameter that does not need the configuration; throws ConfigError.
void validate(const SimConfig& c);

/// What a run will cost, estimated before it starts (run/sim_config.cpp says how).
struct RunEstimate {
  double compression_steps = 0, relaxation_steps = 0, output_points = 0, memory_bytes = 0;
  /// The largest change of packing in one step (at phi_stop, where it is largest).
  double packing_per_step = 0;
};
RunEstimate estimate_run(const SimConfig& c, std::int64_t n);

/// Documented limits of one run; beyond them a run is refused unless forced (--force), since
/// such a run is almost always a typo (--dt 1e-300, --phi-step 1e-12) that would run for ever
/// or exhaust memory.
constexpr double kMaxSteps = 1e10;        // compression or relaxation steps
constexpr double kMaxOutputPoints = 1e6;  // output points of one run
/// ... and memory beyond half of this machine's physical memory.
double memory_limit_bytes();

/// Refuses, with the estimate, a run beyond the limits above (unless `force`), and always a
/// run whose single step compresses by more than phi_step (it would skip output points:
/// shorten dt). n is the particle count (from the configuration or a data file).
void validate_cost(const SimConfig& c, std::int64_t n, bool force);

/// Every parameter that changes the numbers of a run, as text: runs (and checkpoints) with
/// equal fingerprints produce identical results.
std::string fingerprint(const SimConfig& c);

/// Every parameter that changes the relaxed start (the key of a start cache).
std::string relaxation_fingerprint(const SimConfig& c);

/// The length a periodic box must exceed for the minimum image convention to hold: twice the
/// interaction range, 2 (contact distance + neighbor skin). Below it a particle can touch two
/// images of another, and the forces and contacts of one image alone are wrong. The one rule of
/// `jam sim` (validate_box) and `jam import frames`.
double minimum_image_box_length(double max_contact_distance, double skin);

/// Checks that the box at phi_stop is longer than minimum_image_box_length; throws ConfigError.
void validate_box(const SimConfig& c, double box_length_at_stop, double max_contact_distance);

}  // namespace jam
