#include "sim/io/run_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <type_traits>
#include <variant>

#include "sim/io/atomic_file.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/fnv1a.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/run/run_parameters.hpp"
#include "sim/version.hpp"

namespace jam {
namespace {

// Schema 1 files: the datasets covered by their data_checksum, in this order (those present).
constexpr const char* kChecksummed[] = {
    "packing_fraction",    "pressure", "contacts_per_particle",
    "energy_per_particle", "time",     "contacts_per_particle_no_rattlers",
    "rattler_fraction",    "stress"};

/// Adds each dataset's name and the bytes of its values (schema 1's data_checksum).
void add_to_checksum(Fnv1a& h, const std::string& name, const std::vector<double>& v) {
  h.add(name);
  h.add(v.data(), v.size() * sizeof(double));
}

// The most output points a run file holds (sim_config.hpp's kMaxOutputPoints, beyond which a
// run is refused).
constexpr auto kMaxRunFilePoints = static_cast<std::size_t>(kMaxOutputPoints);

}  // namespace

RunFileCheck check_run_file(const std::string& path) {
  RunFileCheck result;
  auto problem = [&result](std::string why) {
    result.problem = std::move(why);
    return result;
  };
  try {
    const h5::File f = h5::File::open_read(path);
    if (!f.has_attribute("complete") || f.read_attribute_int("complete") != 1) {
      return problem("run file is incomplete (no complete = 1)");
    }
    if (f.has_attribute("checksum")) {
      // Schema 2: one checksum over every attribute and dataset.
      if (std::string why = seal_problem(f); !why.empty()) return problem(why);
      result.verified = true;
    } else if (!f.has_attribute("data_checksum")) {
      return problem("run file has no checksum");
    }
    const std::vector<double> phi =
        f.read_dataset("packing_fraction", h5::at_most(kMaxRunFilePoints));
    const std::size_t m = phi.size();
    Fnv1a h;
    for (const char* name : kChecksummed) {
      if (!f.has_dataset(name)) continue;
      // One entry per output point; the stress a D x D matrix per point (D = 2 or 3).
      const bool stress = std::string(name) == "stress";
      const std::vector<double> v =
          f.read_dataset(name, stress ? h5::at_most(9 * m) : h5::exactly(m));
      add_to_checksum(h, name, v);
      if (stress && v.size() != 4 * m && v.size() != 9 * m) {
        return problem(fmt::format("dataset stress has {} values for {} points", v.size(), m));
      }
    }
    // Schema 1 (no "checksum"): only the datasets were checksummed; such a file stays readable
    // but is flagged as unverified, since its attributes could have changed unnoticed.
    if (!result.verified && f.read_attribute_string("data_checksum") != h.hex()) {
      return problem(fmt::format("data checksum {} does not match the stored {}", h.hex(),
                                 f.read_attribute_string("data_checksum")));
    }
    for (std::size_t k = 0; k < phi.size(); ++k) {
      if (!std::isfinite(phi[k]) || (k > 0 && !(phi[k] > phi[k - 1]))) {
        return problem(
            fmt::format("packing_fraction[{}] = {} is not finite and increasing", k, phi[k]));
      }
    }
  } catch (const std::exception& e) {
    return problem(e.what());
  }
  return result;
}

std::string run_file_problem(const std::string& path) {
  return check_run_file(path).problem;
}

namespace {

/// "key=value" words of a fingerprint.
std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> w;
  std::istringstream in(text);
  for (std::string word; in >> word;) w.push_back(word);
  return w;
}

std::string differences(const std::vector<std::string>& stored,
                        const std::vector<std::string>& planned) {
  std::string out;
  for (std::size_t k = 0; k < std::max(stored.size(), planned.size()); ++k) {
    const std::string a = k < stored.size() ? stored[k] : "-";
    const std::string b = k < planned.size() ? planned[k] : "-";
    if (a != b) out += fmt::format("{}{} (planned {})", out.empty() ? "" : ", ", a, b);
  }
  return out;
}

/// A schema-1 file's parameters, in the words of a fingerprint.
std::vector<std::string> stored_parameters(const h5::File& f) {
  auto g = [&f](const char* name) { return fmt::format("{:.17g}", f.read_attribute_double(name)); };
  return {"dim=" + std::to_string(f.read_attribute_int("dim")),
          "n=" + std::to_string(f.read_attribute_int("n")),
          "phi_stop=" + g("phi_stop"),
          "phi_step=" + g("phi_step"),
          "rate=" + g("compression_rate"),
          "dt=" + g("dt"),
          "dynamics=" + f.read_attribute_string("dynamics"),
          "integrator=" + f.read_attribute_string("integrator"),
          "q=" + g("q"),
          "seed=" + std::to_string(f.read_attribute_int("seed")),
          "skin=" + g("skin"),
          "diameter_ratio=" + g("diameter_ratio"),
          "relax=" + std::to_string(f.read_attribute_int("relax")),
          "relax_energy=" + g("relax_energy")};
}

std::vector<std::string> planned_parameters(const SimConfig& c) {
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  return {"dim=" + std::to_string(c.dim),
          "n=" + std::to_string(c.n),
          "phi_stop=" + g(c.phi_stop),
          "phi_step=" + g(c.phi_step),
          "rate=" + g(c.compression_rate),
          "dt=" + g(c.dt),
          "dynamics=" + c.dynamics,
          "integrator=" + c.resolved_integrator(),
          "q=" + g(c.dynamics == "inertial" ? c.quality_factor : 0.0),
          "seed=" + std::to_string(static_cast<std::int64_t>(c.seed)),
          "skin=" + g(c.skin),
          "diameter_ratio=" + g(c.diameter_ratio),
          "relax=" + std::to_string(int{c.relax}),
          "relax_energy=" + g(c.resolved_relax_energy())};
}

}  // namespace

std::string run_identity_problem(const std::string& path, const SimConfig& planned) {
  try {
    const h5::File f = h5::File::open_read(path);
    const std::string diff = f.has_attribute("fingerprint")
                                 ? differences(words(f.read_attribute_string("fingerprint")),
                                               words(fingerprint(planned)))
                                 : differences(stored_parameters(f), planned_parameters(planned));
    return diff.empty() ? "" : "run file belongs to another run: " + diff;
  } catch (const std::exception& e) {
    return e.what();
  }
}

std::optional<std::string> stored_fingerprint(const std::string& path) {
  try {
    const h5::File f = h5::File::open_read(path);
    if (!f.has_attribute("fingerprint")) return std::nullopt;
    return f.read_attribute_string("fingerprint");
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

namespace {

/// The run's parameters (run_parameters.cpp): integers and flags as int64, numbers as float64,
/// words as strings. N, phi_init and the integrator are the ones the run found (from a data
/// file, the dynamics' default).
void write_parameter_attributes(h5::File& f, const SimConfig& c, const RunMetadata& meta) {
  SimConfig run = c;
  run.n = meta.n;
  run.phi_init = meta.phi_init;
  run.integrator = meta.integrator;
  for (const RunParameter& p : run_parameters()) {
    if (p.attribute.empty()) continue;
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::string>) {
            f.write_attribute(p.attribute, v);
          } else {
            f.write_attribute(p.attribute, static_cast<std::int64_t>(v));
          }
        },
        stored_value(run, p));
  }
}

}  // namespace

template <int D>
void write_run_file(const std::string& path, const SimConfig& c, const RunMetadata& meta,
                    const std::vector<Observables<D>>& points) {
  const std::string temporary = AtomicFile::temporary_name(path);
  try {
    h5::File f = h5::File::create(temporary);
    write_parameter_attributes(f, c, meta);
    f.write_attribute("initial_box_length", meta.initial_box_length);
    f.write_attribute("initial_configuration", meta.initial_configuration);
    f.write_attribute("relax_steps", meta.relax_steps);
    f.write_attribute("relax_converged", std::int64_t{meta.relax_converged});
    f.write_attribute("steps", meta.steps);
    f.write_attribute("force_evaluations", meta.force_evaluations);
    f.write_attribute("version", std::string(kVersion));
    f.write_attribute("schema_version", std::int64_t{kRunFileSchemaVersion});
    f.write_attribute("fingerprint", fingerprint(c));
    f.write_attribute("units", std::string(kRunFileUnits));
    if (!c.campaign.empty()) f.write_attribute("campaign", c.campaign);
    if (c.sample >= 0) f.write_attribute("sample", c.sample);
    if (c.jamming_point) {
      f.write_attribute("jamming_packing_fraction", meta.jamming_packing_fraction);
      f.write_attribute("jamming_minimizations", meta.jamming_minimizations);
      f.write_attribute(
          "jamming_definition",
          std::string("lowest packing whose configuration, FIRE-minimized at fixed box "
                      "to max force < 1e-10, keeps pressure > 1e-8; bisection over "
                      "output points, refined by affine compression to 1e-5"));
    }

    const std::size_t m = points.size();
    std::vector<double> phi(m), p(m), z(m), e(m), t(m);
    for (std::size_t k = 0; k < m; ++k) {
      phi[k] = points[k].packing_fraction;
      p[k] = points[k].pressure;
      z[k] = points[k].contacts_per_particle;
      e[k] = points[k].energy_per_particle;
      t[k] = points[k].time;
    }
    f.write_dataset("packing_fraction", phi);
    f.write_dataset("pressure", p);
    f.write_dataset("contacts_per_particle", z);
    f.write_dataset("energy_per_particle", e);
    f.write_dataset("time", t);
    if (c.rattlers) {
      std::vector<double> znr(m), frac(m);
      for (std::size_t k = 0; k < m; ++k) {
        znr[k] = points[k].contacts_per_particle_no_rattlers;
        frac[k] = points[k].rattler_fraction;
      }
      f.write_dataset("contacts_per_particle_no_rattlers", znr);
      f.write_dataset("rattler_fraction", frac);
    }
    if (c.stress) {
      std::vector<double> s;
      s.reserve(m * D * D);
      for (const auto& pt : points)
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) s.push_back(pt.stress[a][b]);
      f.write_dataset("stress", s, {m, static_cast<hsize_t>(D), static_cast<hsize_t>(D)});
    }
    // Each dataset says its unit (an attribute "units").
    for (const auto& [name, unit] :
         {std::pair{"packing_fraction", "1"}, std::pair{"pressure", "k_e/d_s^D"},
          std::pair{"contacts_per_particle", "1"}, std::pair{"energy_per_particle", "k_e"},
          std::pair{"time", "t0"}, std::pair{"contacts_per_particle_no_rattlers", "1"},
          std::pair{"rattler_fraction", "1"}, std::pair{"stress", "k_e/d_s^D"}}) {
      if (f.has_dataset(name)) f.write_attribute("units", std::string(unit), name);
    }
    f.write_attribute("complete", std::int64_t{1});
    seal(f);
    f.close();
    AtomicFile::publish(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

template void write_run_file<2>(const std::string&, const SimConfig&, const RunMetadata&,
                                const std::vector<Observables<2>>&);
template void write_run_file<3>(const std::string&, const SimConfig&, const RunMetadata&,
                                const std::vector<Observables<3>>&);

}  // namespace jam
