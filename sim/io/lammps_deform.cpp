#include "sim/io/lammps_deform.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <stdexcept>

#include "sim/io/lammps_log.hpp"

namespace jam {
namespace {

constexpr std::array<const char*, 3> kAxes = {"x", "y", "z"};
constexpr std::array<const char*, 6> kParameters = {"x", "y", "z", "xy", "xz", "yz"};

/// The words after a parameter's style, per LAMMPS's fix deform (unknown styles: none).
std::size_t style_arguments(const std::string& parameter, const std::string& style) {
  const bool tilt = parameter.size() == 2;
  if (style == "final" || style == "delta") return tilt ? 1 : 2;
  if (style == "wiggle" || style == "variable") return 2;
  if (style == "scale" || style == "vel" || style == "erate" || style == "trate" ||
      style == "pressure")
    return 1;
  return 0;
}

bool is_parameter(const std::string& word) {
  return std::find(kParameters.begin(), kParameters.end(), word) != kParameters.end();
}

/// "x trate -0.001, y final" and, for each axis of the box it leaves alone, "z not deformed".
std::string describe(const LammpsDeform& d, int dim) {
  std::string out;
  auto add = [&](const std::string& part) { out += (out.empty() ? "" : ", ") + part; };
  for (const char* p : kParameters) {
    const auto style = d.styles.find(p);
    if (style == d.styles.end()) continue;
    const auto trate = d.trates.find(p);
    add(trate == d.trates.end() ? fmt::format("{} {}", p, style->second)
                                : fmt::format("{} {} {:g}", p, style->second, trate->second));
  }
  for (int a = 0; a < dim; ++a)
    if (!d.styles.count(kAxes[static_cast<std::size_t>(a)]))
      add(fmt::format("{} not deformed", kAxes[static_cast<std::size_t>(a)]));
  return out;
}

/// Whether `d` compresses every axis of a `dim`-dimensional box alike (and nothing else).
bool isotropic(const LammpsDeform& d, int dim) {
  if (d.styles.size() != static_cast<std::size_t>(dim)) return false;  // a tilt, or an axis left
  const std::string& style = d.styles.begin()->second;
  for (int a = 0; a < dim; ++a) {
    const auto s = d.styles.find(kAxes[static_cast<std::size_t>(a)]);
    if (s == d.styles.end() || s->second != style) return false;
  }
  // Where the log shows the values, they are one value.
  if (!d.trates.empty() && std::any_of(d.trates.begin(), d.trates.end(), [&](const auto& t) {
        return t.second != d.trates.begin()->second;
      }))
    return false;
  return true;
}

constexpr const char* kInstead =
    "name a volume or packing_fraction column (e.g. --column volume=Volume) instead of the time";

}  // namespace

std::optional<LammpsDeform> parse_lammps_deform(const std::vector<std::string>& w, int line,
                                                const std::string& where) {
  if (w.size() < 4 || w[0] != "fix" || (w[3] != "deform" && w[3].rfind("deform/", 0) != 0))
    return std::nullopt;
  LammpsDeform d;
  d.line = line;
  d.id = w[1];
  // fix ID group deform N, then parameters with their styles and arguments, then keywords.
  for (std::size_t k = 5; k < w.size();) {
    if (!is_parameter(w[k])) {
      k += w[k] == "remap" || w[k] == "flip" || w[k] == "units" ? 2 : 1;  // keyword and value
      continue;
    }
    const std::string& parameter = w[k];
    const std::string style = k + 1 < w.size() ? w[k + 1] : "";
    d.styles[parameter] = style;
    if (style == "trate" && k + 2 < w.size()) {
      const std::string& value = w[k + 2];
      // A value given through a variable is shown substituted only in the echo's later lines.
      if (!value.empty() && value[0] != '$' && value[0] != 'v' &&
          value.find("${") == std::string::npos) {
        const double rate = -lammps_number(value, where, "trate");
        // The rates jam simulates (log10 in [-12, 0]); a compression, so trate is negative.
        if (!(rate >= 1e-12 && rate <= 1.0))
          throw std::runtime_error(fmt::format(
              "{}: trate {} (must be a compression, -1 <= trate <= -1e-12)", where, value));
        d.trates[parameter] = -rate;
      }
    }
    k += 2 + style_arguments(parameter, style);
  }
  return d;
}

void check_isotropic_deforms(const std::vector<LammpsDeform>& deforms, int dim,
                             const std::string& log) {
  const LammpsDeform* first_rate = nullptr;
  for (const LammpsDeform& d : deforms) {
    if (!isotropic(d, dim))
      throw std::runtime_error(fmt::format(
          "{}:{}: fix {} deform: {}: not an isotropic compression (the model compresses every "
          "axis of the box, {}, at one trate); a log of another protocol cannot be imported",
          log, d.line, d.id, describe(d, dim), dim == 2 ? "x and y" : "x, y and z"));
    if (d.trates.empty()) continue;
    if (!first_rate) {
      first_rate = &d;
    } else if (d.trates.begin()->second != first_rate->trates.begin()->second) {
      throw std::runtime_error(fmt::format(
          "{}:{}: fix {} deform: trate {:g}, but the fix {} deform of line {} has trate {:g}: a "
          "run of the model has one rate; import a log of one rate",
          log, d.line, d.id, d.trates.begin()->second, first_rate->id, first_rate->line,
          first_rate->trates.begin()->second));
    }
  }
}

void check_packing_from_time(const std::vector<LammpsDeform>& deforms, const std::vector<int>& runs,
                             int first_row, const std::string& log) {
  if (runs.size() > 1)
    throw std::runtime_error(
        fmt::format("{}:{}: a second run (the first at line {}): the packing cannot follow from "
                    "the time and one rate across runs (a relaxation, or a rate changed between "
                    "them); {}",
                    log, runs[1], runs[0], kInstead));
  if (deforms.empty())
    throw std::runtime_error(
        fmt::format("{}: no fix deform line: the packing cannot follow from the time without the "
                    "log's own rate; {}",
                    log, kInstead));
  if (deforms.size() > 1)
    throw std::runtime_error(fmt::format(
        "{}:{}: a second fix deform (the first at line {}): the packing cannot follow from the "
        "time and one rate; {}",
        log, deforms[1].line, deforms[0].line, kInstead));
  const LammpsDeform& d = deforms.front();
  if (d.trates.size() != d.styles.size())
    throw std::runtime_error(fmt::format(
        "{}:{}: fix {} deform: its trate is not shown (a variable, or a style other than trate): "
        "the packing cannot follow from the time; {}",
        log, d.line, d.id, kInstead));
  if (d.line > first_row)
    throw std::runtime_error(fmt::format(
        "{}:{}: fix {} deform comes after the first thermo row (line {}): the packing cannot "
        "follow from the time; {}",
        log, d.line, d.id, first_row, kInstead));
}

}  // namespace jam
