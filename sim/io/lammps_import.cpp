#include "sim/io/lammps_import.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "sim/initial_state.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/lammps_deform.hpp"
#include "sim/io/lammps_log.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/io/whole_number.hpp"

namespace jam {
namespace {

/// The thermo must describe one compression forward in time: increasing finite times and whole
/// steps, non-negative energies and contact numbers. Anything else would make a run file that
/// jam's own checks call corrupt.
void check_thermo(const LammpsThermo& d, const std::string& path) {
  for (std::size_t k = 1; k < d.time.size(); ++k) {
    if (!(d.time[k] > d.time[k - 1]) || !(d.step[k] > d.step[k - 1])) {
      throw std::runtime_error(fmt::format(
          "{}: thermo line {}: Time {} (Step {}) does not follow Time {} (Step {}): times must "
          "increase",
          path, k + 1, d.time[k], d.step[k], d.time[k - 1], d.step[k - 1]));
    }
  }
  for (std::size_t k = 0; k < d.time.size(); ++k) {
    if (!whole_number(d.step[k], 0, kMaxExactWhole)) {
      throw std::runtime_error(
          fmt::format("{}: thermo line {}: Step {} is not a whole number in [0, 2^53]", path, k + 1,
                      d.step[k]));
    }
    if (d.energy[k] < 0 || d.contacts[k] < 0) {
      throw std::runtime_error(fmt::format("{}: thermo line {}: PotEng {} or v_Z {} is negative",
                                           path, k + 1, d.energy[k], d.contacts[k]));
    }
  }
}

}  // namespace

LammpsThermo read_lammps_thermo(const std::string& path) {
  LammpsLog log = read_lammps_log(path, {"Step", "Time", "c_virial", "PotEng", "v_Z"});
  if (!log.dim) throw std::runtime_error(fmt::format("{}: no 'dimension 2|3' line", path));
  if (!log.timestep) throw std::runtime_error(fmt::format("{}: no 'timestep' line", path));
  if (!log.rate)
    throw std::runtime_error(fmt::format("{}: no 'fix ... deform ... trate -rate' line", path));
  // phi follows from the start's box, the time and this rate: one run under one deform.
  check_isotropic_deforms(log.deforms, *log.dim, path);
  check_packing_from_time(log.deforms, log.runs, log.lines.front(), path);
  LammpsThermo d;
  d.dim = *log.dim;
  d.dt = *log.timestep;
  d.rate = *log.rate;
  d.step = std::move(log.columns["Step"]);
  d.time = std::move(log.columns["Time"]);
  d.pressure = std::move(log.columns["c_virial"]);
  d.energy = std::move(log.columns["PotEng"]);
  d.contacts = std::move(log.columns["v_Z"]);
  if (d.time.size() < 2)
    throw std::runtime_error(fmt::format("{}: fewer than 2 thermo lines", path));
  check_thermo(d, path);
  return d;
}

namespace {

double small_mass(const std::string& path) {
  check_input_file("--data", path);
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto w0 = lammps_words(line);
    if (w0.size() == 1 && w0[0] == "Masses") {
      while (std::getline(in, line)) {
        const auto w = lammps_words(line);
        if (w.size() >= 2 && w[0] == "1") {
          const double m = lammps_number(w[1], path + ": Masses", "mass of type 1");
          if (!(m > 0))
            throw std::runtime_error(
                fmt::format("{}: Masses: mass of type 1 {} (must be > 0)", path, w[1]));
          return m;
        }
      }
    }
  }
  throw std::runtime_error(fmt::format("{}: no mass for type 1 (Masses section)", path));
}

template <int D>
void import_dimension(const LammpsImport& r, const LammpsThermo& log) {
  const LammpsData<D> start = read_lammps_data<D>(r.data);
  const Species<D> species;
  const double volume = total_particle_volume(start.particles, species);
  const double phi0 = volume / std::pow(start.box_length, D);
  SimConfig c;
  c.dim = D;
  c.n = static_cast<std::int64_t>(start.particles.size());
  c.compression_rate = log.rate;
  c.dt = log.dt;
  c.dynamics = "inertial";
  c.integrator = "lammps";
  c.quality_factor = std::sqrt(small_mass(r.data)) * D / 2.0;
  c.seed = 0;
  c.relax = false;
  c.phi_step = 0.0;  // the thermo interval sets the output points, not a packing grid
  std::vector<Observables<D>> points;
  for (std::size_t k = 0; k < log.time.size(); ++k) {
    Observables<D> o;
    o.time = log.time[k];
    o.packing_fraction = phi0 * std::exp(D * log.rate * log.time[k]);
    if (!(log.time[k] >= 0) || !(o.packing_fraction < 1.0)) {
      throw std::runtime_error(fmt::format(
          "{}: thermo line {}: Time {} gives packing fraction {:g} from {:g} at trate -{:g} (times "
          "must be >= 0 and the packing below 1)",
          r.log, k + 1, log.time[k], o.packing_fraction, phi0, log.rate));
    }
    o.pressure = log.pressure[k];
    o.contacts_per_particle = log.contacts[k];
    o.energy_per_particle = log.energy[k];
    points.push_back(o);
  }
  c.phi_init = phi0;
  c.phi_stop = points.back().packing_fraction;
  RunMetadata meta;
  meta.n = c.n;
  meta.phi_init = phi0;
  meta.initial_box_length = start.box_length;
  meta.integrator = "lammps: fix nve + fix viscous + fix deform trate remap x";
  meta.initial_configuration = r.data;
  meta.steps = static_cast<std::int64_t>(log.step.back());
  meta.relax_converged = true;
  write_run_file<D>(r.out, c, meta, points);
}

}  // namespace

void import_lammps_run(const LammpsImport& r) {
  const LammpsThermo log = read_lammps_thermo(r.log);
  if (log.dim == 2) {
    import_dimension<2>(r, log);
  } else {
    import_dimension<3>(r, log);
  }
}

}  // namespace jam

namespace jam {
namespace {

/// One model parameter from the command line and from the log: they must agree when both are
/// there, and one of them must be.
template <class T>
T agreed(const std::optional<T>& given, const std::optional<T>& logged, const char* option,
         const char* in_log, const std::string& path) {
  if (given && logged && std::abs(static_cast<double>(*given) - static_cast<double>(*logged)) >
                             1e-9 * std::abs(static_cast<double>(*logged)))
    throw std::runtime_error(fmt::format("{} {} but {}'s {} is {}", option, *given, path, in_log,
                                         *logged));
  if (given) return *given;
  if (logged) return *logged;
  throw std::runtime_error(
      fmt::format("{}: missing (the log does not state its {}; give it)", option, in_log));
}

}  // namespace

const std::vector<std::string>& lammps_import_fields() {
  static const std::vector<std::string> fields = {
      "pressure", "packing_fraction", "volume", "time", "step", "contacts_per_particle",
      "energy_per_particle"};
  return fields;
}

void import_lammps_log(const LammpsImport& r) {
  const auto& known = lammps_import_fields();
  std::vector<std::string> names;
  for (const auto& [field, column] : r.columns) {
    if (std::find(known.begin(), known.end(), field) == known.end())
      throw std::runtime_error(fmt::format("--column {}={}: unknown field {} (fields: pressure, "
                                           "packing_fraction, volume, time, step, "
                                           "contacts_per_particle, energy_per_particle)",
                                           field, column, field));
    names.push_back(column);
  }
  auto has = [&](const char* f) { return r.columns.count(f) > 0; };
  if (!has("pressure")) throw std::runtime_error("--column pressure=COLUMN: missing");
  if (!has("packing_fraction") && !has("volume") && !has("time") && !has("step"))
    throw std::runtime_error(
        "--column: name packing_fraction, volume, time or step (the packing follows from one)");
  if (!r.diameter_ratio)
    throw std::runtime_error(
        "--diameter-ratio: missing (a LAMMPS log does not state the model's diameters; give it)");
  if (!r.sample) throw std::runtime_error("--sample: missing (the run's sample id, >= 0)");
  const LammpsLog log = read_lammps_log(r.log, names);
  auto column = [&](const char* f) { return log.columns.at(r.columns.at(f)); };
  OpenRun run;
  run.dim = agreed<int>(r.dim, log.dim, "--dim", "dimension", r.log);
  // The model is an isotropic compression at one rate, whatever gives the packing.
  check_isotropic_deforms(log.deforms, run.dim, r.log);
  run.compression_rate = agreed<double>(r.rate, log.rate, "--rate", "fix deform trate", r.log);
  run.n = agreed<std::int64_t>(r.n, log.atoms, "--n", "atoms", r.log);
  run.diameter_ratio = *r.diameter_ratio;
  run.contact = r.contact;
  run.sample = *r.sample;
  if (r.quality_factor) run.dynamics = "inertial", run.quality_factor = *r.quality_factor;
  run.simulator = "lammps";
  run.simulator_version = log.version;
  run.source = r.log;
  run.source_checksum = file_checksum(r.log);
  run.interpolation = "none: the thermo rows as LAMMPS printed them";
  run.pressure = column("pressure");
  const std::size_t m = run.pressure.size();
  if (m < 2) throw std::runtime_error(fmt::format("{}: fewer than 2 thermo rows", r.log));
  // Times from the first row: a compression that follows an equilibration starts there.
  if (has("time")) {
    run.time = column("time");
    const double t0 = run.time.front();
    for (double& t : run.time) t -= t0;
  } else if (has("step") && log.timestep) {
    const auto step = column("step");
    for (double s : step) run.time.push_back((s - step.front()) * *log.timestep);
  }
  if (has("packing_fraction")) {
    run.packing_fraction = column("packing_fraction");
  } else if (has("volume")) {
    for (double v : column("volume")) {
      if (!(v > 0))
        throw std::runtime_error(fmt::format("{}: volume {} is not positive", r.log, v));
      run.packing_fraction.push_back(packing_fraction_of(run.dim, run.n, run.diameter_ratio,
                                                         std::pow(v, 1.0 / run.dim)));
    }
  }
  if (!run.packing_fraction.empty()) {
    run.phi_init = r.phi_init.value_or(run.packing_fraction.front());
    if (std::abs(run.packing_fraction.front() / run.phi_init - 1) > 1e-6)
      throw std::runtime_error(fmt::format(
          "--phi-init {} but {}'s first row has packing fraction {:.9g} (N {}, diameter ratio "
          "{})",
          run.phi_init, r.log, run.packing_fraction.front(), run.n, run.diameter_ratio));
  } else {
    if (!r.phi_init)
      throw std::runtime_error("--phi-init: missing (the packing follows from it and the time)");
    if (run.time.empty())
      throw std::runtime_error(fmt::format("{}: no timestep line to turn steps into times", r.log));
    check_packing_from_time(log.deforms, log.runs, log.lines.front(), r.log);
    run.phi_init = *r.phi_init;
    for (double t : run.time)
      run.packing_fraction.push_back(run.phi_init * std::exp(run.dim * run.compression_rate * t));
  }
  if (has("contacts_per_particle")) run.contacts_per_particle = column("contacts_per_particle");
  if (has("energy_per_particle")) run.energy_per_particle = column("energy_per_particle");
  write_open_run(r.out, run);
}

}  // namespace jam
