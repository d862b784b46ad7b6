#include "sim/io/lammps_import.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "sim/initial_state.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/run_file.hpp"

namespace jam {
namespace {

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

}  // namespace

LammpsThermo read_lammps_thermo(const std::string& path) {
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
    if (w[0] == "dimension" && w.size() == 2 && w[1] != "${dim}") d.dim = std::stoi(w[1]);
    if (w[0] == "timestep" && w.size() == 2 && w[1][0] != '$') d.dt = std::stod(w[1]);
    if (w[0] == "fix" && w.size() > 5 && w[3] == "deform") {
      for (std::size_t k = 4; k + 2 < w.size(); ++k) {
        if (w[k + 1] == "trate" && w[k + 2][0] != '$') d.rate = -std::stod(w[k + 2]);
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
        if (header[k] == name) return std::stod(w[k]);
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
  return d;
}

namespace {

double small_mass(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto w0 = words(line);
    if (w0.size() == 1 && w0[0] == "Masses") {
      while (std::getline(in, line)) {
        const auto w = words(line);
        if (w.size() >= 2 && w[0] == "1") return std::stod(w[1]);
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
