#include "sim/io/open_run_schema.hpp"

#include <fmt/format.h>

#include <string_view>

#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/open_run_limits.hpp"

namespace jam {
namespace {

/// A TOML basic string: quotes, backslashes and control characters escaped.
std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// A TOML float that reads back as the same double (and as a float, not an integer).
std::string real(double x) {
  std::string s = fmt::format("{}", x);
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

template <class Words>
std::string list(const Words& words) {
  std::string out = "[";
  for (const auto& w : words) out += (out.size() > 1 ? ", " : "") + quoted(w);
  return out + "]";
}

// One root attribute of an open run: its TOML table's lines after name, type and required.
struct Attribute {
  const char* name;
  const char* type;      // "string", "integer" or "float"
  const char* required;  // "yes", "no", or "inertial" (with dynamics inertial, absent otherwise)
  std::string rule;      // the machine-readable constraints, TOML lines
};

std::vector<Attribute> attributes(const OpenRunSchema& schema) {
  const OpenRunLimits& l = kOpenRunLimits;
  std::vector<std::string_view> dynamics(kDynamics.begin(), kDynamics.end());
  return {
      {"format", "string", "yes", fmt::format("equals = {}\n", quoted(kOpenRunFormat))},
      {"format_version", "integer", "yes", fmt::format("equals = {}\n", kOpenRunFormatVersion)},
      {"dim", "integer", "yes", "allowed = [2, 3]\n"},
      {"n", "integer", "yes", fmt::format("min = 2\nmax = {}\neven = true\n", l.max_whole)},
      {"diameter_ratio", "float", "yes",
       fmt::format("min = {}\nmax = {}\n", real(l.diameter_ratio_min), real(l.diameter_ratio_max))},
      {"contact", "string", "yes", fmt::format("allowed = {}\n", list(schema.contacts))},
      {"dynamics", "string", "yes", fmt::format("allowed = {}\n", list(dynamics))},
      {"q", "float", "inertial", "above = 0.0\nfinite = true\n"},
      {"protocol", "string", "yes", fmt::format("equals = {}\n", quoted(kOpenRunProtocol))},
      {"compression_rate", "float", "yes", "units = \"1/t0\"\nabove = 0.0\nfinite = true\n"},
      {"phi_init", "float", "yes", "above = 0.0\nbelow = 1.0\n"},
      {"simulator", "string", "yes", "not_blank = true\n"},
      {"simulator_version", "string", "yes", ""},
      {"sample", "integer", "yes", fmt::format("min = 0\nmax = {}\n", l.max_whole)},
      {"units", "string", "yes", "equals = \"jam\"\n"},
      {"jamming_packing_fraction", "float", "no",
       fmt::format("above = {}\nbelow = {}\nnan_allowed = true\n", real(l.jamming_above),
                   real(l.jamming_below))},
      {"source", "string", "no", ""},
      {"source_checksum", "string", "no", "pattern = \"[0-9a-fA-F]{16}\"\n"},
      {"interpolation", "string", "no", ""},
  };
}

std::string series_rules(std::string_view name) {
  const OpenRunLimits& l = kOpenRunLimits;
  if (name == "packing_fraction")
    return "above = 0.0\nbelow = 1.0\nincreasing = true\nfirst_at_least = \"phi_init\"\n";
  if (name == "contacts_per_particle")
    return fmt::format("min = 0.0\nmax = {}\n", real(l.max_contacts_per_particle));
  if (name == "time") return "min = 0.0\nincreasing = true\n";
  return "min = 0.0\n";
}

void limit(std::string& out, const char* name, const std::string& values, const char* why) {
  out += fmt::format("\n[limits.{}]\n{}why = {}\n", name, values, quoted(why));
}

std::string limits() {
  const OpenRunLimits& l = kOpenRunLimits;
  using Why = OpenRunLimitReasons;
  std::string out;
  limit(out, "max_whole", fmt::format("value = {}\n", l.max_whole), Why::max_whole);
  limit(out, "max_points", fmt::format("value = {}\n", l.max_points), Why::max_points);
  limit(out, "diameter_ratio",
        fmt::format("min = {}\nmax = {}\n", real(l.diameter_ratio_min), real(l.diameter_ratio_max)),
        Why::diameter_ratio);
  limit(out, "max_contacts_per_particle",
        fmt::format("value = {}\n", real(l.max_contacts_per_particle)),
        Why::max_contacts_per_particle);
  limit(out, "jamming_packing_fraction",
        fmt::format("above = {}\nbelow = {}\n", real(l.jamming_above), real(l.jamming_below)),
        Why::jamming_packing_fraction);
  limit(out, "phi_init_slack", fmt::format("value = {}\n", real(l.phi_init_slack)),
        Why::phi_init_slack);
  limit(out, "rate_tolerance", fmt::format("value = {}\n", real(l.rate_tolerance)),
        Why::rate_tolerance);
  limit(out, "max_frame_particles", fmt::format("value = {}\n", l.max_frame_particles),
        Why::max_frame_particles);
  limit(out, "max_frames", fmt::format("value = {}\n", l.max_frames), Why::max_frames);
  return out;
}

std::string registries(const OpenRunSchema& schema) {
  std::string out;
  for (std::size_t k = 0; k < schema.contacts.size(); ++k)
    out += fmt::format("\n[[contact_law]]\nname = {}\nformula = {}\ndefault = {}\n",
                       quoted(schema.contacts[k]), quoted(schema.formulas[k]), k == 0);
  for (const IntegratorInfo& i : kIntegrators)
    out += fmt::format(
        "\n[[integrator]]\nname = {}\ndynamics = {}\nadaptive = {}\norder = {}\n"
        "force_evaluations = {}\n",
        quoted(i.name), quoted(i.dynamics), i.force_evaluations == 0, i.order, i.force_evaluations);
  return out;
}

}  // namespace

const OpenRunSchema& open_run_schema() {
  static const OpenRunSchema schema = open_run_schema_of<ContactLaws>();
  return schema;
}

std::string open_run_schema_toml(const OpenRunSchema& schema) {
  std::string out =
      "# The open run format (docs/cross-simulator.md, docs/file-formats.md) and its frames\n"
      "# file: every field with its type, shape, units and allowed values, the limits with their\n"
      "# reasons, the contact laws and integrators of this jam. Written by `jam schema open-run`\n"
      "# from the tables jam validates with (sim/io/open_run_schema.cpp); jamio validates with\n"
      "# this file (python/jamio/open_run.py). Do not edit: tests/test_open_run_schema.py fails\n"
      "# when it is not what jam writes (regenerate: jam schema open-run > this file).\n";
  out += fmt::format("\nformat = {}\nformat_version = {}\nprotocol = {}\nunits = \"jam\"\n",
                     quoted(kOpenRunFormat), kOpenRunFormatVersion, quoted(kOpenRunProtocol));
  for (const Attribute& a : attributes(schema))
    out += fmt::format("\n[[attribute]]\nname = {}\ntype = {}\nrequired = {}\n{}", quoted(a.name),
                       quoted(a.type), quoted(a.required), a.rule);
  for (const OpenRunSeries& s : kOpenRunSeries)
    out += fmt::format(
        "\n[[dataset]]\nname = {}\ntype = \"float\"\nshape = [\"M\"]\nunits = {}\nrequired = "
        "{}\nfinite = true\n{}",
        quoted(s.name), quoted(s.unit), s.required, series_rules(s.name));
  // The frames file (`jam import frames`): the attributes above, these datasets.
  const char* frames[][4] = {{"box_length", "[\"M\"]", "d_s", "true"},
                             {"positions", "[\"M\", \"n\", \"dim\"]", "d_s", "true"},
                             {"diameters", "[\"n\"]", "d_s", "true"},
                             {"time", "[\"M\"]", "t0", "false"}};
  for (const auto& d : frames)
    out += fmt::format(
        "\n[[frames_dataset]]\nname = {}\ntype = \"float\"\nshape = {}\nunits = {}\nrequired = "
        "{}\n",
        quoted(d[0]), d[1], quoted(d[2]), d[3]);
  return out + limits() + registries(schema);
}

}  // namespace jam
