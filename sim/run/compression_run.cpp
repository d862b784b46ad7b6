#include "sim/run/compression_run.hpp"

#include <fmt/format.h>

#include <utility>

#include "sim/dynamics/integrators.hpp"
#include "sim/initial_state.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/run/compression_phases.hpp"
#include "sim/run/run_inputs.hpp"

namespace jam {
namespace {

/// The integrator named by the config, on a system of the config's contact law.
template <int D, class Contact>
RunSummary run_with(const SimConfig& c, const RunControl& control, ParticleData<D> particles,
                    const Species<D>& species, const CompressingBox<D>& box, RunMetadata meta) {
  // Relaxation happens at zero rate: the box starts at rest (CompressionRun starts it).
  CompressingBox<D> at_rest = box;
  at_rest.compression_rate = 0.0;
  System<D, Contact> sys(std::move(particles), species, at_rest, c.skin);
  sys.set_threads(c.threads);
  const StepperOptions options{c.quality_factor, c.relaxation_tolerance(), c.dt};
  return with_integrator<D>(meta.integrator, sys.size(), options,
                            [&]<class Stepper>(Stepper& stepper) {
                              return detail::CompressionRun<D, Contact, Stepper>(
                                         c, control, sys, stepper, box, std::move(meta))
                                  .run();
                            });
}

template <int D>
RunSummary run_dimension(const SimConfig& c, const RunControl& control) {
  const Species<D> species(c.diameter_ratio);
  Start<D> start = make_start<D>(c, species);
  CompressingBox<D> box;
  box.initial_length = start.box_length;
  box.compression_rate = c.compression_rate;
  box.particle_volume = total_particle_volume(start.particles, species);

  RunMetadata meta;
  meta.n = static_cast<std::int64_t>(start.particles.size());
  meta.phi_init = box.packing_fraction(0.0);
  meta.initial_box_length = start.box_length;
  meta.integrator = c.resolved_integrator();
  meta.initial_configuration = start.description;
  if (meta.phi_init >= c.phi_stop) {
    throw ConfigError(fmt::format("--phi-stop {:g}: must be above the packing of {} ({:.6g})",
                                  c.phi_stop, start.description, meta.phi_init));
  }
  if (!c.write_start.empty() && c.write_start_at <= meta.phi_init) {
    throw ConfigError(
        fmt::format("--write-start-at {:g}: must lie above the packing of {} ({:.6g})",
                    c.write_start_at, start.description, meta.phi_init));
  }
  if (!c.read_lammps_data.empty()) validate_cost(c, meta.n, c.force);  // now that N is known
  SimConfig checked = c;
  checked.n = meta.n;
  validate_box(checked, CompressingBox<D>::length_for_packing(box.particle_volume, c.phi_stop),
               species.max_contact_distance);

  return with_contact_law(c.contact, [&]<class Contact>() {
    return run_with<D, Contact>(c, control, std::move(start.particles), species, box, meta);
  });
}

}  // namespace

namespace {
template <int D>
void validate_generated_box_in(const SimConfig& c) {
  const Species<D> species(c.diameter_ratio);
  const double half = static_cast<double>(c.n / 2);
  const double volume = half * (species.volume[0] + species.volume[1]);
  validate_box(c, CompressingBox<D>::length_for_packing(volume, c.phi_stop),
               species.max_contact_distance);
}
}  // namespace

void validate_generated_box(const SimConfig& c) {
  if (c.dim == 2) {
    validate_generated_box_in<2>(c);
  } else {
    validate_generated_box_in<3>(c);
  }
}

RunSummary run_compression(const SimConfig& config, const RunControl& control) {
  validate(config);
  // Before anything is allocated: a typo such as --n 2000000000 is refused, not attempted.
  if (config.read_lammps_data.empty()) validate_cost(config, config.n, config.force);
  SimConfig c = config;
  c.out = checked_writable("out", c.out);
  if (!c.write_lammps_data.empty()) {
    c.write_lammps_data = checked_writable("write-lammps-data", c.write_lammps_data);
  }
  if (!c.write_final_lammps_data.empty()) {
    c.write_final_lammps_data =
        checked_writable("write-final-lammps-data", c.write_final_lammps_data);
  }
  if (!c.write_start.empty()) c.write_start = checked_writable("write-start", c.write_start);
  return c.dim == 2 ? run_dimension<2>(c, control) : run_dimension<3>(c, control);
}

}  // namespace jam
