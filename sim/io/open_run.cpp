#include "sim/io/open_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/fnv1a.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run_limits.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/model/species.hpp"

namespace jam {
namespace {

using Field = OpenRunSeries;
constexpr const auto& kFields = kOpenRunSeries;

[[noreturn]] void refuse(const std::string& where, const std::string& what) {
  throw std::runtime_error(fmt::format("{}: {}", where, what));
}

bool blank(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); });
}

bool hex16(const std::string& s) {
  return s.size() == 16 &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isxdigit(c); });
}

}  // namespace

void validate_open_run_model(const OpenRun& r, const std::string& where,
                             const OpenRunSchema& schema) {
  const OpenRunLimits& lim = open_run_limits();
  if (r.dim != 2 && r.dim != 3) refuse(where, fmt::format("dim {} must be 2 or 3", r.dim));
  if (r.n < 2 || r.n % 2 != 0 || r.n > lim.max_whole)
    refuse(where,
           fmt::format("n {} must be even, >= 2 (half small, half big) and at most 2^53", r.n));
  if (!(r.diameter_ratio >= lim.diameter_ratio_min && r.diameter_ratio <= lim.diameter_ratio_max))
    refuse(where, fmt::format("diameter_ratio {} must be in [{}, {}]", r.diameter_ratio,
                              lim.diameter_ratio_min, lim.diameter_ratio_max));
  if (std::find(schema.contacts.begin(), schema.contacts.end(), r.contact) == schema.contacts.end())
    refuse(where, fmt::format("contact '{}' must be {}", r.contact, or_list(schema.contacts)));
  if (r.dynamics == "inertial") {
    if (!(r.quality_factor > 0.0 && std::isfinite(r.quality_factor)))
      refuse(where,
             fmt::format("q {} must be > 0 and finite for inertial dynamics", r.quality_factor));
  } else if (r.dynamics != "overdamped") {
    refuse(where, fmt::format("dynamics '{}' must be {}", r.dynamics, or_list(kDynamics)));
  } else if (r.quality_factor != 0.0) {
    refuse(where, fmt::format("q {} is only for dynamics 'inertial' (dynamics is 'overdamped')",
                              r.quality_factor));
  }
}

namespace {

void check_attributes(const OpenRun& r, const std::string& where, const OpenRunSchema& schema) {
  const OpenRunLimits& lim = open_run_limits();
  validate_open_run_model(r, where, schema);
  if (!(r.compression_rate > 0.0 && std::isfinite(r.compression_rate)))
    refuse(where, fmt::format("compression_rate {} must be > 0 and finite", r.compression_rate));
  if (!(r.phi_init > 0.0 && r.phi_init < 1.0))
    refuse(where, fmt::format("phi_init {} must be in (0, 1)", r.phi_init));
  if (blank(r.simulator)) refuse(where, "simulator is empty (name the code that ran it)");
  if (r.sample < 0 || r.sample > lim.max_whole)
    refuse(where, fmt::format("sample {} must be >= 0 and at most 2^53", r.sample));
  if (const auto& j = r.jamming_packing_fraction;
      j && !std::isnan(*j) && !(*j > lim.jamming_above && *j < lim.jamming_below))
    refuse(where, fmt::format("jamming_packing_fraction {} must be in ({}, {}), or NaN when not "
                              "found",
                              *j, lim.jamming_above, lim.jamming_below));
  if (!r.source_checksum.empty() && !hex16(r.source_checksum))
    refuse(where, fmt::format("source_checksum '{}' must be 16 hex digits (FNV-1a of the source)",
                              r.source_checksum));
}

/// The spec's rule for each dataset's values, point by point.
void check_values(const OpenRun& r, const std::string& where) {
  const std::size_t m = r.packing_fraction.size();
  if (m < 2) refuse(where, fmt::format("packing_fraction has {} points, at least 2 needed", m));
  for (const Field& f : kFields) {
    const auto& v = r.*f.values;
    if (!f.required && v.empty()) continue;
    if (v.size() != m)
      refuse(where, fmt::format("{} has {} points, packing_fraction {}", f.name, v.size(), m));
    for (std::size_t k = 0; k < m; ++k)
      if (!std::isfinite(v[k]))
        refuse(where, fmt::format("{}[{}] = {} is not finite", f.name, k, v[k]));
  }
  const OpenRunLimits& lim = open_run_limits();
  if (m > static_cast<std::size_t>(lim.max_points))
    refuse(where, fmt::format("packing_fraction has {} points, at most {}", m, lim.max_points));
  const auto& phi = r.packing_fraction;
  if (!(phi[0] >= r.phi_init * (1 - lim.phi_init_slack)))
    refuse(where, fmt::format("packing_fraction[0] = {} is below phi_init {}", phi[0], r.phi_init));
  for (std::size_t k = 0; k < m; ++k) {
    if (!(phi[k] > 0.0 && phi[k] < 1.0))
      refuse(where, fmt::format("packing_fraction[{}] = {} is not in (0, 1)", k, phi[k]));
    if (k > 0 && !(phi[k] > phi[k - 1]))
      refuse(where, fmt::format("packing_fraction[{}] = {} does not increase (previous {})", k,
                                phi[k], phi[k - 1]));
    if (r.pressure[k] < 0)
      refuse(where, fmt::format("pressure[{}] = {} is negative", k, r.pressure[k]));
    if (!r.contacts_per_particle.empty() &&
        !(r.contacts_per_particle[k] >= 0 &&
          r.contacts_per_particle[k] <= lim.max_contacts_per_particle))
      refuse(where, fmt::format("contacts_per_particle[{}] = {} must be in [0, {}]", k,
                                r.contacts_per_particle[k], lim.max_contacts_per_particle));
    if (!r.energy_per_particle.empty() && r.energy_per_particle[k] < 0)
      refuse(where,
             fmt::format("energy_per_particle[{}] = {} is negative", k, r.energy_per_particle[k]));
  }
  if (r.time.empty()) return;
  for (std::size_t k = 0; k < m; ++k) {
    if (r.time[k] < 0 || (k > 0 && !(r.time[k] > r.time[k - 1])))
      refuse(where, fmt::format("time[{}] = {} is negative or does not increase", k, r.time[k]));
    // The protocol: L(t) = L0 exp(-rate t), so phi(t) = phi_init exp(D rate t).
    const double expected = r.phi_init * std::exp(r.dim * r.compression_rate * r.time[k]);
    if (!(std::abs(phi[k] / expected - 1.0) <= lim.rate_tolerance))
      refuse(where, fmt::format("packing_fraction[{}] = {:.9g} at time {:g}, but phi_init {:g} "
                                "compressed at rate {:g} gives {:.9g}: the box does not shrink "
                                "at the stated rate",
                                k, phi[k], r.time[k], r.phi_init, r.compression_rate, expected));
  }
}

std::string string_or(const h5::File& f, const char* name, std::string otherwise) {
  return f.has_attribute(name) ? f.read_attribute_string(name) : std::move(otherwise);
}

std::string required_string(const h5::File& f, const char* name) {
  if (!f.has_attribute(name))
    throw std::runtime_error(fmt::format("{}: missing attribute '{}'", f.path(), name));
  return f.read_attribute_string(name);
}

double required_number(const h5::File& f, const char* name) {
  if (!f.has_attribute(name))
    throw std::runtime_error(fmt::format("{}: missing attribute '{}'", f.path(), name));
  return f.read_attribute_double(name);
}

std::int64_t required_int(const h5::File& f, const char* name) {
  if (!f.has_attribute(name))
    throw std::runtime_error(fmt::format("{}: missing attribute '{}'", f.path(), name));
  return f.read_attribute_int(name);
}

void read_datasets(const h5::File& f, OpenRun& r) {
  for (const Field& field : kFields) {
    if (!f.has_dataset(field.name)) {
      if (field.required)
        throw std::runtime_error(fmt::format("{}: missing dataset '{}'", f.path(), field.name));
      continue;
    }
    const auto shape = f.dataset_shape(field.name);
    if (shape.size() != 1)
      throw std::runtime_error(fmt::format("{}: dataset '{}' has rank {}, expected a list (rank 1)",
                                           f.path(), field.name, shape.size()));
    const auto most = static_cast<std::size_t>(open_run_limits().max_points);
    const std::size_t m = r.packing_fraction.empty() ? most : r.packing_fraction.size();
    // Floating point only, as the format says: an integer series is refused, not converted.
    r.*field.values = f.read_float_dataset(
        field.name, r.packing_fraction.empty() ? h5::at_most(m) : h5::exactly(m));
    if (f.has_attribute("units", field.name)) {
      const std::string unit = f.read_attribute_string("units", field.name);
      if (unit != field.unit)
        throw std::runtime_error(fmt::format("{}: dataset '{}' has units '{}', expected '{}'",
                                             f.path(), field.name, unit, field.unit));
    }
  }
}

}  // namespace

void validate_open_run(const OpenRun& r, const std::string& where, const OpenRunSchema& schema) {
  check_attributes(r, where, schema);
  check_values(r, where);
}

OpenRun read_open_run(const std::string& path, const OpenRunSchema& schema) {
  check_input_file("run", path);
  OpenRun r;
  {
    const h5::File f = h5::File::open_read(path);
    r.jam_native = !f.has_attribute("format") && f.has_attribute("checksum");
    if (!r.jam_native) {
      const std::string format = required_string(f, "format");
      if (format != kOpenRunFormat)
        throw std::runtime_error(
            fmt::format("{}: format '{}' is not {}", path, format, kOpenRunFormat));
      const std::int64_t version = required_int(f, "format_version");
      if (version != kOpenRunFormatVersion)
        throw std::runtime_error(fmt::format("{}: format_version {} (this jam reads {})", path,
                                             version, kOpenRunFormatVersion));
      const std::string protocol = required_string(f, "protocol");
      if (protocol != kOpenRunProtocol)
        throw std::runtime_error(
            fmt::format("{}: protocol '{}' is not {}", path, protocol, kOpenRunProtocol));
      const std::string units = required_string(f, "units");
      if (units != "jam")
        throw std::runtime_error(fmt::format(
            "{}: units '{}' must be jam (d_s, k_e, t0: docs/cross-simulator.md)", path, units));
    }
    r.dim = static_cast<int>(std::clamp<std::int64_t>(required_int(f, "dim"), -1, 4));
    r.n = required_int(f, "n");
    r.diameter_ratio = required_number(f, "diameter_ratio");
    r.contact = r.jam_native ? string_or(f, "contact", "harmonic") : required_string(f, "contact");
    r.dynamics = required_string(f, "dynamics");
    if (r.dynamics == "inertial") {
      r.quality_factor = required_number(f, "q");
    } else if (f.has_attribute("q")) {
      // jam's own run files store Q 0 for overdamped runs; an open run states q only when
      // inertial (check_model refuses any other value).
      r.quality_factor = f.read_attribute_double("q");
      if (!r.jam_native && r.quality_factor == 0.0)
        throw std::runtime_error(fmt::format(
            "{}: q 0 is only for dynamics 'inertial' (dynamics is '{}')", path, r.dynamics));
    }
    r.compression_rate = required_number(f, "compression_rate");
    r.phi_init = required_number(f, "phi_init");
    r.simulator = r.jam_native ? "jam" : required_string(f, "simulator");
    r.simulator_version =
        r.jam_native ? string_or(f, "version", "") : required_string(f, "simulator_version");
    r.sample = r.jam_native && !f.has_attribute("sample") ? 0 : required_int(f, "sample");
    if (f.has_attribute("jamming_packing_fraction"))
      r.jamming_packing_fraction = f.read_attribute_double("jamming_packing_fraction");
    r.source = string_or(f, "source", "");
    r.source_checksum = string_or(f, "source_checksum", "");
    r.interpolation = string_or(f, "interpolation", "");
    read_datasets(f, r);
  }
  // jam's own: its checksum covers every attribute and dataset (run_file.hpp).
  if (r.jam_native)
    if (const std::string why = run_file_problem(path); !why.empty())
      throw std::runtime_error(fmt::format("{}: {}", path, why));
  validate_open_run(r, path, schema);
  return r;
}

void write_open_run(const std::string& path, const OpenRun& r, const OpenRunSchema& schema) {
  if (r.jam_native) throw std::logic_error("write_open_run: jam's own runs have their writer");
  validate_open_run(r, path, schema);
  const std::string target = output_file_target(path);
  const std::string temporary = AtomicFile::temporary_name(target);
  try {
    h5::File f = h5::File::create(temporary);
    f.write_attribute("format", std::string(kOpenRunFormat));
    f.write_attribute("format_version", kOpenRunFormatVersion);
    f.write_attribute("protocol", std::string(kOpenRunProtocol));
    f.write_attribute("units", std::string("jam"));
    f.write_attribute("dim", std::int64_t{r.dim});
    f.write_attribute("n", r.n);
    f.write_attribute("diameter_ratio", r.diameter_ratio);
    f.write_attribute("contact", r.contact);
    f.write_attribute("dynamics", r.dynamics);
    if (r.dynamics == "inertial") f.write_attribute("q", r.quality_factor);
    f.write_attribute("compression_rate", r.compression_rate);
    f.write_attribute("phi_init", r.phi_init);
    f.write_attribute("simulator", r.simulator);
    f.write_attribute("simulator_version", r.simulator_version);
    f.write_attribute("sample", r.sample);
    if (r.jamming_packing_fraction)
      f.write_attribute("jamming_packing_fraction", *r.jamming_packing_fraction);
    if (!r.source.empty()) f.write_attribute("source", r.source);
    if (!r.source_checksum.empty()) f.write_attribute("source_checksum", r.source_checksum);
    if (!r.interpolation.empty()) f.write_attribute("interpolation", r.interpolation);
    for (const Field& field : kFields) {
      const auto& v = r.*field.values;
      if (v.empty()) continue;
      f.write_dataset(field.name, v);
      f.write_attribute("units", std::string(field.unit), field.name);
    }
    f.close();
    AtomicFile::publish(target);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

std::string file_checksum(const std::string& path) {
  check_input_file("file", path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read", path));
  Fnv1a h;
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    h.add(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  return h.hex();
}

double packing_fraction_of(int dim, std::int64_t n, double diameter_ratio, double box_length) {
  const double half = static_cast<double>(n) / 2.0;
  const double volume = dim == 2
                            ? half * (sphere_volume<2>(1.0) + sphere_volume<2>(diameter_ratio))
                            : half * (sphere_volume<3>(1.0) + sphere_volume<3>(diameter_ratio));
  return volume / std::pow(box_length, dim);
}

}  // namespace jam
