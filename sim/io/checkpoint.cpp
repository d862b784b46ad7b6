#include "sim/io/checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/particle_datasets.hpp"
#include "sim/io/sealed_file.hpp"
#include "sim/run/sim_config.hpp"

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
    f.write_attribute("force_evaluations", state.force_evaluations);
    f.write_attribute("next_output", state.next_output);
    f.write_attribute("time", state.time);
    f.write_attribute("relax_time", state.relax_time);
    f.write_attribute("cpu_seconds", state.cpu_seconds);
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
    // Every saved packing; the positions of those the jamming-point search still keeps (1 in
    // saved_kept: one contiguous bracket once the search has released the rest).
    std::vector<double> saved_phi, saved_s;
    std::vector<std::uint32_t> saved_kept;
    for (const auto& c : state.saved) {
      saved_phi.push_back(c.packing_fraction);
      saved_kept.push_back(c.s.empty() ? 0 : 1);
      saved_s.insert(saved_s.end(), c.s.begin(), c.s.end());
    }
    f.write_dataset("saved_packing_fraction", saved_phi);
    f.write_dataset("saved_kept", saved_kept);
    f.write_dataset("saved_s", saved_s);
    f.write_dataset("jamming_answers", state.jamming_answers);
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

namespace {

constexpr auto kMaxPoints = static_cast<std::size_t>(kMaxOutputPoints);

/// Integer attribute `name`, refused (naming the file, the field and its value) outside
/// [lo, hi]: a run indexes its output times with next_output and counts steps from these.
std::int64_t read_in_range(const h5::File& f, const char* name, std::int64_t lo, std::int64_t hi) {
  const std::int64_t v = f.read_attribute_int(name);
  if (v < lo || v > hi) {
    throw std::runtime_error(
        fmt::format("{}: attribute '{}' = {} is outside [{}, {}]", f.path(), name, v, lo, hi));
  }
  return v;
}

double read_finite(const h5::File& f, const char* name) {
  const double v = f.read_attribute_double(name);
  if (!std::isfinite(v)) {
    throw std::runtime_error(
        fmt::format("{}: attribute '{}' = {} is not finite", f.path(), name, v));
  }
  return v;
}

template <int D>
void read_counters(const h5::File& f, RunState<D>& s) {
  constexpr std::int64_t kMaxSteps = std::numeric_limits<std::int64_t>::max() / 2;
  s.phase = read_in_range(f, "phase", RunState<D>::kRelaxing, RunState<D>::kCompressing);
  s.relax_steps = read_in_range(f, "relax_steps", 0, kMaxSteps);
  s.relax_converged = f.read_attribute_int("relax_converged") != 0;
  s.steps = read_in_range(f, "steps", 0, kMaxSteps);
  // Checkpoints from before the count have none: it then counts from the resume.
  if (f.has_attribute("force_evaluations"))
    s.force_evaluations = read_in_range(f, "force_evaluations", 0, kMaxSteps);
  s.next_output = read_in_range(f, "next_output", 0, static_cast<std::int64_t>(kMaxPoints));
  // Times of adaptive steps (fixed-step runs compute theirs from the step count).
  if (f.has_attribute("time")) s.time = read_finite(f, "time");
  if (f.has_attribute("relax_time")) s.relax_time = read_finite(f, "relax_time");
  // Checkpoints from before the count have none: the earlier attempts' cost is then unknown.
  if (f.has_attribute("cpu_seconds")) {
    s.cpu_seconds = read_finite(f, "cpu_seconds");
    if (s.cpu_seconds < 0.0) {
      throw std::runtime_error(
          fmt::format("{}: attribute 'cpu_seconds' = {} is negative", f.path(), s.cpu_seconds));
    }
  }
}

/// The output points so far: every points_* column has one entry per point, the stress D x D.
template <int D>
void read_points(const h5::File& f, RunState<D>& s) {
  const std::size_t m = f.read_dataset("points_time", h5::at_most(kMaxPoints)).size();
  s.points.resize(m);
  for (int k = 0; k < 7; ++k) {
    const auto column =
        f.read_dataset(std::string("points_") + kObservableFields[k], h5::exactly(m));
    for (std::size_t i = 0; i < m; ++i) field(s.points[i], k) = column[i];
  }
  const auto stress = f.read_dataset("points_stress", h5::exactly(m * D * D));
  std::size_t at = 0;
  for (auto& pt : s.points)
    for (auto& row : pt.stress)
      for (auto& x : row) x = stress[at++];
}

/// The configurations kept for the jamming point: D x n scaled positions each.
template <int D>
void read_saved(const h5::File& f, RunState<D>& s, std::size_t n) {
  const auto saved_phi = f.read_dataset("saved_packing_fraction", h5::at_most(kMaxPoints));
  const std::size_t per = D * n;
  // Checkpoints from before the search released configurations keep them all.
  std::vector<std::uint32_t> kept(saved_phi.size(), 1);
  if (f.has_dataset("saved_kept"))
    kept = f.read_dataset_u32("saved_kept", h5::exactly(saved_phi.size()));
  std::size_t runs_of_kept = 0, count = 0;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    if (kept[k] > 1) {
      throw std::runtime_error(
          fmt::format("{}: dataset 'saved_kept' holds {}, not 0 or 1", f.path(), kept[k]));
    }
    count += kept[k];
    runs_of_kept += kept[k] == 1 && (k == 0 || kept[k - 1] == 0);
  }
  if (runs_of_kept > 1 || (count < kept.size() && count < 2)) {
    throw std::runtime_error(fmt::format(
        "{}: dataset 'saved_kept' keeps {} of {} configurations, not one bracket of at least 2",
        f.path(), count, kept.size()));
  }
  const auto saved_s = f.read_dataset("saved_s", h5::exactly(count * per));
  auto first = saved_s.begin();
  for (std::size_t k = 0; k < saved_phi.size(); ++k) {
    s.saved.push_back({saved_phi[k], {}});
    if (kept[k] == 0) continue;
    s.saved.back().s.assign(first, first + static_cast<long>(per));
    first += static_cast<long>(per);
  }
  // A stopped jamming-point search's decisions (0 or 1 each); checkpoints from before they
  // were kept have none, and the search then starts over. A bisection over at most kMaxPoints
  // configurations and its refinement to 1e-5 take far fewer than kMaxAnswers.
  constexpr std::size_t kMaxAnswers = 256;
  if (!f.has_dataset("jamming_answers")) return;
  s.jamming_answers = f.read_dataset_u32("jamming_answers", h5::at_most(kMaxAnswers));
  for (const std::uint32_t a : s.jamming_answers) {
    if (a > 1) {
      throw std::runtime_error(
          fmt::format("{}: dataset 'jamming_answers' holds {}, not 0 or 1", f.path(), a));
    }
  }
}

/// The integrator's fields. The integrators copy a per-particle field whole and index it by
/// particle, so each holds one value per particle, except the two scalars.
StepperState read_stepper(const h5::File& f, std::size_t n) {
  constexpr std::int64_t kMaxFields = 64;  // the integrators keep at most 2 D + 1
  StepperState stepper;
  const std::int64_t fields = read_in_range(f, "stepper_fields", 0, kMaxFields);
  for (std::int64_t k = 0; k < fields; ++k) {
    const std::string name = f.read_attribute_string(fmt::format("stepper_field_{}", k));
    // Shapes: one value (the next step, a flag), the stiffest-mode estimate and its age (two),
    // or one per particle (velocities, forces).
    const std::size_t size = name == "h_next" || name == "have_forces" ? 1
                             : name == "stiffest_mode"                 ? 2
                                                                       : n;
    stepper.emplace_back(name, f.read_dataset("stepper_" + name, h5::exactly(size)));
  }
  return stepper;
}

}  // namespace

template <int D>
Checkpoint<D> read_checkpoint_data(const std::string& path) {
  const h5::File f = h5::File::open_read(path);
  Checkpoint<D> c;
  read_counters(f, c.state);
  c.particles = read_particles<D>(f, path);
  read_points(f, c.state);
  read_saved(f, c.state, c.particles.size());
  c.stepper = read_stepper(f, c.particles.size());
  return c;
}

template void write_checkpoint<2>(const std::string&, const std::string&, const RunState<2>&,
                                  const ParticleData<2>&, const StepperState&);
template void write_checkpoint<3>(const std::string&, const std::string&, const RunState<3>&,
                                  const ParticleData<3>&, const StepperState&);
template std::optional<Checkpoint<2>> read_checkpoint<2>(const std::string&, const std::string&);
template std::optional<Checkpoint<3>> read_checkpoint<3>(const std::string&, const std::string&);

}  // namespace jam
