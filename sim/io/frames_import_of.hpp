#pragma once
// `jam import frames` for any list of contact laws (frames_import.hpp): the binary's own
// (ContactLaws, frames_import.cpp) or a test's longer list (tests/open_run_registry_tool.cpp),
// which shows that a new law is imported with no edit here.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/dynamics/system.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/open_run_limits.hpp"
#include "sim/io/open_run_schema.hpp"
#include "sim/io/output_path.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {
namespace frames_detail {

/// The open run's attributes of a frames file (the datasets come from the measurement), its
/// model checked by the open run format's rules (validate_open_run_model, the schema's contact
/// laws), and n by the frames file's own bound (it holds M x N x D positions).
inline OpenRun frames_attributes(const h5::File& f, const OpenRunSchema& schema) {
  auto need = [&](const char* name) {
    if (!f.has_attribute(name))
      throw std::runtime_error(fmt::format("{}: missing attribute '{}'", f.path(), name));
  };
  OpenRun r;
  for (const char* name : {"dim", "n", "diameter_ratio", "contact", "compression_rate", "phi_init",
                           "simulator", "simulator_version", "sample"})
    need(name);
  const std::int64_t dim = f.read_attribute_int("dim");
  r.n = f.read_attribute_int("n");
  r.diameter_ratio = f.read_attribute_double("diameter_ratio");
  r.contact = f.read_attribute_string("contact");
  r.dynamics = f.has_attribute("dynamics") ? f.read_attribute_string("dynamics") : "overdamped";
  if (r.dynamics == "inertial") need("q"), r.quality_factor = f.read_attribute_double("q");
  r.compression_rate = f.read_attribute_double("compression_rate");
  r.phi_init = f.read_attribute_double("phi_init");
  r.simulator = f.read_attribute_string("simulator");
  r.simulator_version = f.read_attribute_string("simulator_version");
  r.sample = f.read_attribute_int("sample");
  if (f.has_attribute("source")) r.source = f.read_attribute_string("source");
  if (f.has_attribute("source_checksum"))
    r.source_checksum = f.read_attribute_string("source_checksum");
  r.dim = static_cast<int>(std::clamp<std::int64_t>(dim, -1, 4));
  validate_open_run_model(r, f.path(), schema);
  const std::int64_t most = open_run_limits().max_frame_particles;
  if (r.n > most)
    throw std::runtime_error(fmt::format(
        "{}: n {} is more than a frames file holds (at most {}: its positions are read whole)",
        f.path(), r.n, most));
  return r;
}

/// The species of each particle from its diameter: 1 small, diameter_ratio big, half each.
inline std::vector<std::uint8_t> types_of(const std::vector<double>& d, const OpenRun& r,
                                          const std::string& path) {
  std::vector<std::uint8_t> type(d.size());
  std::int64_t big = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (std::abs(d[i] - 1.0) <= 1e-9) {
      type[i] = kSmall;
    } else if (std::abs(d[i] - r.diameter_ratio) <= 1e-9 * r.diameter_ratio) {
      type[i] = kBig, ++big;
    } else {
      throw std::runtime_error(
          fmt::format("{}: diameters[{}] = {} is neither 1 nor the diameter_ratio {}", path, i,
                      d[i], r.diameter_ratio));
    }
  }
  if (r.diameter_ratio != 1.0 && 2 * big != r.n)
    throw std::runtime_error(
        fmt::format("{}: {} big particles of {}, the model has half", path, big, r.n));
  return type;
}

template <int D, class Contact>
void measure_frames(const h5::File& f, OpenRun& r, const std::vector<double>& box_length,
                    const std::vector<std::uint8_t>& type) {
  const std::size_t m = box_length.size(), n = static_cast<std::size_t>(r.n);
  const auto shape = f.dataset_shape("positions");
  if (shape != std::vector<hsize_t>{m, n, static_cast<hsize_t>(D)})
    throw std::runtime_error(
        fmt::format("{}: dataset 'positions' has shape ({}), expected ({}, "
                    "{}, {})",
                    f.path(), fmt::join(shape, ", "), m, n, D));
  const std::vector<double> x = f.read_dataset("positions", h5::exactly(m * n * D));
  const Species<D> species(r.diameter_ratio);
  // jam sim's skin and its rule: a box below twice the interaction range would count one image
  // of a pair that touches two (N = 2 in a small box: half the pressure, Z 1 instead of 2).
  const double skin = SimConfig{}.skin;
  const double bound = minimum_image_box_length(species.max_contact_distance, skin);
  for (std::size_t k = 0; k < m; ++k) {
    const double length = box_length[k];
    if (!(length > bound))
      throw std::runtime_error(fmt::format(
          "{}: frame {}: box length {:.6g} is not larger than twice the interaction range 2 x "
          "({:g} + skin {:g}) = {:.6g}, which jam sim requires (a particle would touch two "
          "images of another); frames of more particles are needed",
          f.path(), k, length, species.max_contact_distance, skin, bound));
    ParticleData<D> p;
    p.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      p.type[i] = type[i];
      p.id[i] = static_cast<std::uint32_t>(i + 1);
      for (int d = 0; d < D; ++d) {
        const double xi = x[(k * n + i) * D + static_cast<std::size_t>(d)];
        if (!std::isfinite(xi))
          throw std::runtime_error(
              fmt::format("{}: positions[{}][{}][{}] = {} is not finite", f.path(), k, i, d, xi));
        p.s[d][i] = wrap_unit(xi / length + 0.5);  // any periodic image
      }
    }
    CompressingBox<D> box;
    box.initial_length = length;
    box.particle_volume = total_particle_volume(p, species);
    System<D, Contact> sys(std::move(p), species, box, skin);
    const Observables<D> o = measure(sys, 0.0, false);
    r.packing_fraction.push_back(o.packing_fraction);
    r.pressure.push_back(o.pressure);
    r.contacts_per_particle.push_back(o.contacts_per_particle);
    r.energy_per_particle.push_back(o.energy_per_particle);
  }
}

}  // namespace frames_detail

/// import_frames (frames_import.hpp) with the contact laws of Laws (a std::tuple of laws).
template <class Laws>
void import_frames_of(const std::string& frames, const std::string& out) {
  using namespace frames_detail;
  const OpenRunSchema schema = open_run_schema_of<Laws>();
  check_input_file("frames", frames);
  OpenRun r;
  {
    const h5::File f = h5::File::open_read(frames);
    r = frames_attributes(f, schema);
    for (const char* name : {"box_length", "diameters", "positions"})
      if (!f.has_dataset(name))
        throw std::runtime_error(fmt::format("{}: missing dataset '{}'", frames, name));
    for (const char* name : {"box_length", "diameters"})
      if (f.dataset_shape(name).size() != 1)
        throw std::runtime_error(fmt::format("{}: dataset '{}' must be a list", frames, name));
    const std::vector<double> box_length = f.read_dataset(
        "box_length", h5::at_most(static_cast<std::size_t>(open_run_limits().max_frames)));
    for (std::size_t k = 0; k < box_length.size(); ++k)
      if (!(box_length[k] > 0 && std::isfinite(box_length[k])))
        throw std::runtime_error(
            fmt::format("{}: box_length[{}] = {} is not a length", frames, k, box_length[k]));
    const std::vector<std::uint8_t> type = types_of(
        f.read_dataset("diameters", h5::exactly(static_cast<std::size_t>(r.n))), r, frames);
    if (f.has_dataset("time")) {
      if (f.dataset_shape("time").size() != 1)
        throw std::runtime_error(fmt::format("{}: dataset 'time' must be a list", frames));
      r.time = f.read_dataset("time", h5::exactly(box_length.size()));
    }
    with_contact_law<Laws>(r.contact, [&]<class Contact>() {
      if (r.dim == 2)
        measure_frames<2, Contact>(f, r, box_length, type);
      else
        measure_frames<3, Contact>(f, r, box_length, type);
      return 0;
    });
  }
  r.interpolation = "none: measured by jam from configurations";
  if (r.source.empty()) r.source = frames;
  write_open_run(out, r, schema);
}

}  // namespace jam
