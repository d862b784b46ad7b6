#include "sim/run/sim_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/parallel.hpp"
#include "sim/run/run_parameters.hpp"

namespace jam {
namespace {

[[noreturn]] void reject(const std::string& option, const std::string& value,
                         const std::string& why) {
  throw ConfigError(fmt::format("--{} {}: {}", option, value, why));
}

std::string str(double v) {
  return fmt::format("{:g}", v);
}

void require_finite_positive(const std::string& option, double v) {
  if (!std::isfinite(v) || v <= 0.0) reject(option, str(v), "must be a finite number > 0");
}

/// Parameters with a list of allowed values (run_parameters.cpp): --dim, --dynamics, ...
void validate_choices(const SimConfig& c) {
  for (const auto& p : run_parameters()) {
    if (p.choices.empty()) continue;
    const std::string value = message_text(field_value(c, p));
    if (std::find(p.choices.begin(), p.choices.end(), value) == p.choices.end()) {
      reject(p.option().substr(2), value.empty() ? "''" : value, "must be " + or_list(p.choices));
    }
  }
}

/// The integrator against the integrator list: one of the dynamics' own.
void validate_integrator(const SimConfig& c) {
  const std::string integ = c.resolved_integrator();
  const IntegratorInfo* info = find_integrator(integ);
  if (!info || info->dynamics != c.dynamics) {
    reject("integrator", integ,
           fmt::format("{} dynamics takes {}", c.dynamics, or_list(integrators_of(c.dynamics))));
  }
}

}  // namespace

namespace {

/// The whole text as a finite number, or NaN (then the caller names the option).
double whole_number(const std::string& text) {
  std::size_t used = 0;
  double v = NAN;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return NAN;
  }
  return used == text.size() && std::isfinite(v) ? v : NAN;
}

/// "auto" (nullopt) or the tolerance as a number; throws ConfigError naming --tolerance.
std::optional<double> explicit_tolerance(const std::string& text) {
  if (text == "auto") return std::nullopt;
  const double v = whole_number(text);
  if (!(v > 0.0)) reject("tolerance", text.empty() ? "''" : text, "must be 'auto' or a number > 0");
  return v;
}

}  // namespace

double SimConfig::resolved_relax_energy() const {
  if (relax_energy == "auto") return 1e-4 * compression_rate * compression_rate;
  const double v = whole_number(relax_energy);
  if (!(v >= 0.0)) reject("relax-energy", relax_energy, "must be 'auto' or a number >= 0");
  return v;
}

double SimConfig::resolved_tolerance() const {
  if (const auto v = explicit_tolerance(tolerance)) return *v;
  return is_adaptive_integrator(resolved_integrator())
             ? auto_tolerance(compression_rate, dense_output, rms_error_norm())
             : kRelaxationTolerance;
}

double SimConfig::relaxation_tolerance() const {
  return explicit_tolerance(tolerance).value_or(kRelaxationTolerance);
}

double SimConfig::resolved_transient_tolerance() const {
  if (!is_adaptive_integrator(resolved_integrator()) || transient_tolerance == "off") return 0.0;
  if (transient_tolerance == "auto") {
    const double tight = relaxation_tolerance();
    return tight < resolved_tolerance() ? tight : 0.0;
  }
  const double v = whole_number(transient_tolerance);
  if (!(v > 0.0)) {
    reject("transient-tolerance", transient_tolerance.empty() ? "''" : transient_tolerance,
           "must be 'auto', 'off' or a number > 0");
  }
  return v;
}

bool SimConfig::resolved_dense_output() const {
  return dense_output && is_adaptive_integrator(resolved_integrator());
}

std::string SimConfig::resolved_stiffest_mode() const {
  return is_adaptive_integrator(resolved_integrator()) ? stiffest_mode : std::string("bound");
}

std::string SimConfig::resolved_error_norm() const {
  return is_adaptive_integrator(resolved_integrator()) ? error_norm : std::string("max");
}

std::uint64_t parse_seed(const std::string& option, const std::string& text) {
  const bool digits = !text.empty() && text.size() <= 19 &&
                      text.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoull(text) > kMaxSeed) {
    reject(option, text.empty() ? "''" : text, "must be an integer in [0, 2^63 - 1]");
  }
  return std::stoull(text);
}

namespace {

/// Chained starts: a continued compression of the overdamped dynamics (the stepper state of
/// inertial runs, their velocities, is not carried), written strictly inside the run.
void validate_chain(const SimConfig& c) {
  if (!c.read_start.empty()) {
    if (c.relax) reject("read-start", c.read_start, "continues a compression: give --relax 0");
    if (!c.read_lammps_data.empty()) {
      reject("read-start", c.read_start, "conflicts with --read-lammps-data");
    }
    if (c.dynamics != "overdamped") {
      reject("read-start", c.read_start, "chained starts are for overdamped dynamics");
    }
  }
  if (!c.write_start.empty()) {
    if (c.dynamics != "overdamped") {
      reject("write-start", c.write_start, "chained starts are for overdamped dynamics");
    }
    const bool inside = c.write_start_at > (c.read_lammps_data.empty() ? c.phi_init : 0.0) &&
                        c.write_start_at < c.phi_stop;
    if (!inside) {
      reject("write-start-at", str(c.write_start_at),
             fmt::format("must lie between --phi-init and --phi-stop ({:g})", c.phi_stop));
    }
  }
}

}  // namespace

void validate(const SimConfig& c) {
  validate_choices(c);
  if (c.read_lammps_data.empty()) {
    if (c.n < 2) reject("n", std::to_string(c.n), "at least 2 particles are needed");
    if (c.n % 2 != 0) {
      reject("n", std::to_string(c.n), "must be even for a 50:50 mixture of small and big");
    }
    if (c.n > (std::int64_t{1} << 31)) reject("n", std::to_string(c.n), "too large");
    if (!std::isfinite(c.phi_init) || c.phi_init <= 0.0 || c.phi_init >= 1.5) {
      reject("phi-init", str(c.phi_init), "must be in (0, 1.5)");
    }
  } else {
    if (c.n_given) reject("n", std::to_string(c.n), "conflicts with --read-lammps-data");
    if (c.phi_init_given) {
      reject("phi-init", str(c.phi_init),
             "conflicts with --read-lammps-data (taken from the file)");
    }
  }
  if (!std::isfinite(c.phi_stop) || c.phi_stop <= 0.0 || c.phi_stop >= 1.5) {
    reject("phi-stop", str(c.phi_stop), "must be in (0, 1.5)");
  }
  if (c.read_lammps_data.empty() && c.phi_init >= c.phi_stop) {
    reject("phi-init", str(c.phi_init), fmt::format("must be below --phi-stop ({:g})", c.phi_stop));
  }
  require_finite_positive("phi-step", c.phi_step);
  require_finite_positive("rate", c.compression_rate);
  require_finite_positive("dt", c.dt);
  require_finite_positive("skin", c.skin);
  // In units of d_s: beyond a few diameters the list holds most of the box and costs memory
  // quadratic in it, with nothing gained (performance.md: 0.1-0.4 hardly differ).
  if (c.skin > 10.0) reject("skin", str(c.skin), "must be in (0, 10]");
  if (c.threads < 1 || c.threads > available_threads()) {
    reject(
        "threads", str(c.threads),
        fmt::format("must be between 1 and {} (the threads available here)", available_threads()));
  }
  if (!std::isfinite(c.diameter_ratio) || c.diameter_ratio < 1.0 || c.diameter_ratio > 2.0) {
    reject("diameter-ratio", str(c.diameter_ratio), "must be in [1, 2]");
  }
  c.resolved_relax_energy();
  c.resolved_tolerance();
  c.resolved_transient_tolerance();
  if (!std::isfinite(c.relax_time_max) || c.relax_time_max < 0.0) {
    reject("relax-time-max", str(c.relax_time_max), "must be >= 0");
  }
  validate_integrator(c);
  if (c.seed > kMaxSeed) reject("seed", std::to_string(c.seed), "must be in [0, 2^63 - 1]");
  if (c.dynamics == "inertial") {
    require_finite_positive("q", c.quality_factor);
    if (c.quality_factor > kMaxQualityFactor) {
      reject("q", str(c.quality_factor),
             "must be in (0, 1]: the inertial model stands for the strongly overdamped "
             "regime (Q < 1)");
    }
    // Explicit drag in velocity Verlet is unstable beyond dt = 2 m_s / gamma_s, which is
    // 2 Q^2 k_d V_s = 4 Q^2 / D in these units.
    const double bound = 4.0 * c.quality_factor * c.quality_factor / c.dim;
    if (c.dt >= bound) {
      reject("dt", str(c.dt),
             fmt::format("unstable for inertial dynamics with --q {:g}: dt must be below "
                         "2 m_s/gamma_s = {:.3g}",
                         c.quality_factor, bound));
    }
  }
  if (!std::isfinite(c.checkpoint_interval) || c.checkpoint_interval < 0.0) {
    reject("checkpoint-interval", str(c.checkpoint_interval), "must be >= 0 seconds");
  }
  if (c.out.empty()) throw ConfigError("--out: a run file name is required");
  validate_chain(c);
}

namespace {

/// The words of a fingerprint: " key=value" for each parameter in `words` (in that order),
/// then the suffixes, in table order, of those that differ from their unmarked values. The
/// values are those of the run, or of its relaxation.
enum class Phase { run, relaxation };
std::string identity_words(const SimConfig& c, const std::vector<const RunParameter*>& words,
                           Phase phase) {
  static const SimConfig defaults;
  std::string text, suffixes;
  for (const RunParameter* p : words) {
    ParameterValue v = phase == Phase::run ? stored_value(c, *p) : stored_relaxation_value(c, *p);
    // A data file gives N and the packing: its name identifies them.
    if (p->from_data_file && !c.read_lammps_data.empty()) v = zero_like(v);
    const std::string word = fmt::format(" {}={}", p->word(), fingerprint_text(v));
    if (p->identity == Identity::word) {
      text += word;
    } else if (v != p->unmarked.value_or(stored_value(defaults, *p))) {
      suffixes += word;
    }
  }
  return text + suffixes;
}

std::vector<const RunParameter*> fingerprint_parameters() {
  std::vector<const RunParameter*> out;
  for (const auto& p : run_parameters())
    if (p.in_fingerprint()) out.push_back(&p);
  return out;
}

std::vector<const RunParameter*> relaxation_parameters() {
  std::vector<const RunParameter*> out;
  for (const auto& p : run_parameters())
    if (p.in_fingerprint() && p.relaxation_position > 0) out.push_back(&p);
  std::stable_sort(out.begin(), out.end(), [](const RunParameter* a, const RunParameter* b) {
    return a->relaxation_position < b->relaxation_position;
  });
  return out;
}

}  // namespace

std::string fingerprint(const SimConfig& c) {
  static const auto words = fingerprint_parameters();
  return identity_words(c, words, Phase::run).substr(1);
}

std::string relaxation_fingerprint(const SimConfig& c) {
  static const auto words = relaxation_parameters();
  return "relaxation" + identity_words(c, words, Phase::relaxation);
}

double minimum_image_box_length(double max_contact_distance, double skin) {
  return 2.0 * (max_contact_distance + skin);
}

void validate_box(const SimConfig& c, double box_length_at_stop, double max_contact_distance) {
  const double bound = minimum_image_box_length(max_contact_distance, c.skin);
  if (!(box_length_at_stop > bound)) {
    throw ConfigError(fmt::format(
        "--n {}: box length {:.4g} at --phi-stop {:g} is not larger than twice the "
        "interaction range 2 x ({:g} + skin {:g}) = {:.4g}",
        c.n, box_length_at_stop, c.phi_stop, max_contact_distance, c.skin, bound));
  }
}

}  // namespace jam
