#include "sim/io/checkpoint.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/particle_datasets.hpp"
#include "sim/io/sealed_file.hpp"

namespace jam {
namespace {

constexpr const char* kObservableFields[] = {"time",
                                             "packing_fraction",
                                             "pressure",
                                             "contacts_per_particle",
                                             "energy_per_particle",
                                             "contacts_per_particle_no_rattlers",
                                             "rattler_fraction"};

template <int D>
double field(const Observables<D>& o, int k) {
  const double fields[] = {o.time,
                           o.packing_fraction,
                           o.pressure,
                           o.contacts_per_particle,
                           o.energy_per_particle,
                           o.contacts_per_particle_no_rattlers,
                           o.rattler_fraction};
  return fields[k];
}

template <int D>
double& field(Observables<D>& o, int k) {
  double* fields[] = {&o.time,
                      &o.packing_fraction,
                      &o.pressure,
                      &o.contacts_per_particle,
                      &o.energy_per_particle,
                      &o.contacts_per_particle_no_rattlers,
                      &o.rattler_fraction};
  return *fields[k];
}

}  // namespace

template <int D>
void write_checkpoint(const std::string& path, const std::string& fingerprint,
                      const RunState<D>& state, const ParticleData<D>& particles,
                      const StepperState& stepper) {
  write_sealed(path, [&](h5::File& f) {
    f.write_attribute("fingerprint", fingerprint);
    f.write_attribute("phase", state.phase);
    f.write_attribute("relax_steps", state.relax_steps);
    f.write_attribute("relax_converged", std::int64_t{state.relax_converged});
    f.write_attribute("steps", state.steps);
    f.write_attribute("next_output", state.next_output);
    f.write_attribute("time", state.time);
    f.write_attribute("relax_time", state.relax_time);
    write_particles(f, particles);
    std::vector<double> column(state.points.size());
    for (int k = 0; k < 7; ++k) {
      for (std::size_t m = 0; m < state.points.size(); ++m) {
        column[m] = field(state.points[m], k);
      }
      f.write_dataset(std::string("points_") + kObservableFields[k], column);
    }
    std::vector<double> stress;
    for (const auto& pt : state.points)
      for (const auto& row : pt.stress) stress.insert(stress.end(), row.begin(), row.end());
    f.write_dataset("points_stress", stress);
    std::vector<double> saved_phi, saved_s;
    for (const auto& c : state.saved) {
      saved_phi.push_back(c.packing_fraction);
      saved_s.insert(saved_s.end(), c.s.begin(), c.s.end());
    }
    f.write_dataset("saved_packing_fraction", saved_phi);
    f.write_dataset("saved_s", saved_s);
    for (const auto& [name, values] : stepper) f.write_dataset("stepper_" + name, values);
    f.write_attribute("stepper_fields", std::int64_t(stepper.size()));
    for (std::size_t k = 0; k < stepper.size(); ++k) {
      f.write_attribute(fmt::format("stepper_field_{}", k), stepper[k].first);
    }
  });
}

template <int D>
Checkpoint<D> read_checkpoint_data(const std::string& path);

template <int D>
std::optional<Checkpoint<D>> read_checkpoint(const std::string& path,
                                             const std::string& fingerprint) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  // The seal first, before HDF5 parses anything: a flipped bit in the fingerprint is damage,
  // not another run, and a damaged file never reaches the HDF5 reader.
  if (const std::string why = sealed_file_problem(path); !why.empty()) throw CorruptCheckpoint(why);
  std::string stored;
  try {
    stored = h5::File::open_read(path).read_attribute_string("fingerprint");
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
  if (stored != fingerprint) {
    throw ForeignCheckpoint(fmt::format(
        "checkpoint '{}' belongs to a run with other parameters; remove it to start afresh", path));
  }
  try {
    return read_checkpoint_data<D>(path);
  } catch (const std::exception& e) {
    throw CorruptCheckpoint(e.what());
  }
}

template <int D>
Checkpoint<D> read_checkpoint_data(const std::string& path) {
  const h5::File f = h5::File::open_read(path);
  Checkpoint<D> c;
  c.state.phase = f.read_attribute_int("phase");
  c.state.relax_steps = f.read_attribute_int("relax_steps");
  c.state.relax_converged = f.read_attribute_int("relax_converged") != 0;
  c.state.steps = f.read_attribute_int("steps");
  c.state.next_output = f.read_attribute_int("next_output");
  // Times of adaptive steps (fixed-step runs compute theirs from the step count).
  if (f.has_attribute("time")) c.state.time = f.read_attribute_double("time");
  if (f.has_attribute("relax_time")) c.state.relax_time = f.read_attribute_double("relax_time");
  c.particles = read_particles<D>(f, path);
  const auto time = f.read_dataset("points_time");
  c.state.points.resize(time.size());
  for (int k = 0; k < 7; ++k) {
    const auto column = f.read_dataset(std::string("points_") + kObservableFields[k]);
    for (std::size_t m = 0; m < column.size(); ++m) field(c.state.points[m], k) = column[m];
  }
  const auto stress = f.read_dataset("points_stress");
  std::size_t at = 0;
  for (auto& pt : c.state.points)
    for (auto& row : pt.stress)
      for (auto& x : row) x = stress.at(at++);
  const auto saved_phi = f.read_dataset("saved_packing_fraction");
  const auto saved_s = f.read_dataset("saved_s");
  const std::size_t per = saved_phi.empty() ? 0 : saved_s.size() / saved_phi.size();
  for (std::size_t k = 0; k < saved_phi.size(); ++k) {
    c.state.saved.push_back(
        {saved_phi[k], std::vector<double>(saved_s.begin() + static_cast<long>(k * per),
                                           saved_s.begin() + static_cast<long>((k + 1) * per))});
  }
  const auto fields = f.read_attribute_int("stepper_fields");
  for (std::int64_t k = 0; k < fields; ++k) {
    const std::string name = f.read_attribute_string(fmt::format("stepper_field_{}", k));
    c.stepper.emplace_back(name, f.read_dataset("stepper_" + name));
  }
  return c;
}

template void write_checkpoint<2>(const std::string&, const std::string&, const RunState<2>&,
                                  const ParticleData<2>&, const StepperState&);
template void write_checkpoint<3>(const std::string&, const std::string&, const RunState<3>&,
                                  const ParticleData<3>&, const StepperState&);
template std::optional<Checkpoint<2>> read_checkpoint<2>(const std::string&, const std::string&);
template std::optional<Checkpoint<3>> read_checkpoint<3>(const std::string&, const std::string&);

}  // namespace jam
