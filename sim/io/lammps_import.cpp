#include "sim/io/lammps_import.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "sim/initial_state.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"

namespace jam {
namespace {

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

/// The whole of `text` as a finite number; otherwise one line naming the file, line, field
/// and value (std::stod would take "1.5abc" as 1.5 and say only "stod" of "abc").
double number(const std::string& text, const std::string& where, const std::string& field) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, v);
  if (error != std::errc() || at != end) {
    throw std::runtime_error(fmt::format("{}: {} '{}' is not a number", where, field, text));
  }
  if (!std::isfinite(v)) {
    throw std::runtime_error(fmt::format("{}: {} {} is not finite", where, field, text));
  }
  return v;
}

/// The thermo must describe one compression forward in time: increasing finite times and steps,
/// non-negative energies and contact numbers. Anything else would make a run file that jam's
/// own checks call corrupt.
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
    if (d.energy[k] < 0 || d.contacts[k] < 0) {
      throw std::runtime_error(fmt::format("{}: thermo line {}: PotEng {} or v_Z {} is negative",
                                           path, k + 1, d.energy[k], d.contacts[k]));
    }
  }
}

}  // namespace

LammpsThermo read_lammps_thermo(const std::string& path) {
  check_input_file("LAMMPS log", path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read LAMMPS log", path));
  LammpsThermo d;
  d.dt = NAN;
  d.rate = NAN;
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    ++line_no;
    const auto w = words(line);
    if (w.empty()) continue;
    const std::string where = fmt::format("{}:{}", path, line_no);
    if (w[0] == "dimension" && w.size() == 2 && w[1] != "${dim}") {
      const double dim = number(w[1], where, "dimension");
      if (dim != 2 && dim != 3) {
        throw std::runtime_error(fmt::format("{}: dimension {} (must be 2 or 3)", where, w[1]));
      }
      d.dim = static_cast<int>(dim);
    }
    if (w[0] == "timestep" && w.size() == 2 && w[1][0] != '$') {
      d.dt = number(w[1], where, "timestep");
      if (!(d.dt > 0))
        throw std::runtime_error(fmt::format("{}: timestep {} (must be > 0)", where, w[1]));
    }
    if (w[0] == "fix" && w.size() > 5 && w[3] == "deform") {
      for (std::size_t k = 4; k + 2 < w.size(); ++k) {
        if (w[k + 1] == "trate" && w[k + 2][0] != '$') {
          d.rate = -number(w[k + 2], where, "trate");
          // The rates jam simulates (campaign log10_rates in [-12, 0]); a compression, so the
          // strain rate is negative.
          if (!(d.rate >= 1e-12 && d.rate <= 1.0)) {
            throw std::runtime_error(fmt::format(
                "{}: trate {} (must be a compression, -1 <= trate <= -1e-12)", where, w[k + 2]));
          }
        }
      }
    }
    if (w[0] == "Step") {
      header = w;
      continue;
    }
    if (w[0] == "Loop") {
      header.clear();
      continue;
    }
    if (header.empty()) continue;
    if (w.size() != header.size()) {
      throw std::runtime_error(fmt::format("{}:{}: thermo line has {} columns, header {}", path,
                                           line_no, w.size(), header.size()));
    }
    auto column = [&](const std::string& name) {
      for (std::size_t k = 0; k < header.size(); ++k)
        if (header[k] == name) return number(w[k], where, name);
      throw std::runtime_error(
          fmt::format("{}:{}: thermo has no column {} (use reference/lammps/compress_inertial.in)",
                      path, line_no, name));
    };
    d.step.push_back(column("Step"));
    d.time.push_back(column("Time"));
    d.pressure.push_back(column("c_virial"));
    d.energy.push_back(column("PotEng"));
    d.contacts.push_back(column("v_Z"));
  }
  if (d.dim != 2 && d.dim != 3)
    throw std::runtime_error(fmt::format("{}: no 'dimension 2|3' line", path));
  if (!(d.dt > 0)) throw std::runtime_error(fmt::format("{}: no 'timestep' line", path));
  if (!(d.rate > 0))
    throw std::runtime_error(fmt::format("{}: no 'fix ... deform ... trate -rate' line", path));
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
    const auto w0 = words(line);
    if (w0.size() == 1 && w0[0] == "Masses") {
      while (std::getline(in, line)) {
        const auto w = words(line);
        if (w.size() >= 2 && w[0] == "1") {
          const double m = number(w[1], path + ": Masses", "mass of type 1");
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
  c.q = std::sqrt(small_mass(r.data)) * D / 2.0;
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
