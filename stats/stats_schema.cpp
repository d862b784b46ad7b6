#include "stats/stats_schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "sim/io/whole_number.hpp"
#include "stats/stats_inputs.hpp"
#include "stats/stats_schema_rules.hpp"

namespace jam::stats {
// Named, not anonymous: jam_stats compiles in unity batches, where anonymous helpers of
// several files meet.
namespace schema_check {

using Dimensions = std::map<std::string, hsize_t>;

[[noreturn]] void refuse(const h5::File& f, const std::string& what) {
  throw std::runtime_error(f.path() + ": " + what);
}

/// "attribute 'n'" at the root, "attribute 'n' of 'ensembles/a'" elsewhere (as h5::File says).
std::string attribute_label(const std::string& name, const std::string& object) {
  return object == "/" ? fmt::format("attribute '{}'", name)
                       : fmt::format("attribute '{}' of '{}'", name, object);
}

/// "2 or 3", "'ok' or 'poor'": the allowed values as a message lists them.
std::string allowed_words(const std::vector<AllowedValue>& allowed) {
  std::string out;
  for (std::size_t k = 0; k < allowed.size(); ++k) {
    if (k > 0) out += k + 1 == allowed.size() ? " or " : ", ";
    const AllowedValue& a = allowed[k];
    out += a.is_string ? fmt::format("'{}'", a.text) : fmt::format("{}", a.number);
  }
  return out;
}

bool allows(const std::vector<AllowedValue>& allowed, double v) {
  return allowed.empty() || std::any_of(allowed.begin(), allowed.end(), [v](const auto& a) {
           return !a.is_string && a.number == v;
         });
}

bool allows(const std::vector<AllowedValue>& allowed, const std::string& s) {
  return allowed.empty() || std::any_of(allowed.begin(), allowed.end(),
                                        [&s](const auto& a) { return a.is_string && a.text == s; });
}

std::string child(const std::string& base, const std::string& name) {
  return base == "/" ? name : base + "/" + name;
}

bool exists(const h5::File& f, const std::string& path) {
  return path == "/" || f.has_dataset(path);
}

/// The groups a pattern names ("ensembles/*/constant_phi"), in name order; a member where
/// `*` stands, or a named step that is not a group, is refused.
std::vector<std::string> instances(const h5::File& f, const std::string& pattern) {
  std::vector<std::string> bases{"/"};
  std::size_t from = 0;
  while (pattern != "/" && from <= pattern.size()) {
    const std::size_t to = std::min(pattern.find('/', from), pattern.size());
    const std::string part = pattern.substr(from, to - from);
    from = to + 1;
    std::vector<std::string> next;
    for (const std::string& base : bases) {
      const std::vector<std::string> names =
          part == "*" ? f.list_group(base) : std::vector<std::string>{part};
      for (const std::string& name : names) {
        const std::string path = child(base, name);
        if (part != "*" && !exists(f, path)) continue;
        if (!f.is_group(path)) refuse(f, fmt::format("'{}' is not a group", path));
        next.push_back(path);
      }
    }
    bases = std::move(next);
  }
  return bases;
}

/// A required group: every instance of its parent has it.
void check_required(const h5::File& f, const std::string& pattern) {
  if (pattern == "/") return;
  const std::size_t slash = pattern.rfind('/');
  const std::string parent = slash == std::string::npos ? "/" : pattern.substr(0, slash);
  const std::string last = slash == std::string::npos ? pattern : pattern.substr(slash + 1);
  for (const std::string& base : instances(f, parent))
    if (!exists(f, child(base, last)))
      refuse(f, fmt::format("group '{}' missing", child(base, last)));
}

bool needed(const h5::File& f, const std::string& object, bool required,
            const std::string& unless) {
  return required || (!unless.empty() && !f.has_attribute(unless, object == "/" ? "." : object));
}

void check_attribute(const h5::File& f, const std::string& object, const AttributeRule& r) {
  const std::string label = attribute_label(r.name, object);
  const std::string at = object == "/" ? "." : object;
  if (!f.has_attribute(r.name, at)) {
    if (needed(f, object, r.required, r.required_unless)) refuse(f, label + " missing");
    return;
  }
  if (r.type == "string") {
    const std::string s = f.read_attribute_string(r.name, at);
    if (!allows(r.allowed, s))
      refuse(f, fmt::format("{} is '{}', not {}", label, s, allowed_words(r.allowed)));
    return;
  }
  const bool integer = r.type == "integer";
  const std::int64_t i = integer ? f.read_attribute_int(r.name, at) : 0;
  const double v = integer ? static_cast<double>(i) : f.read_attribute_double(r.name, at);
  const std::string shown = integer ? std::to_string(i) : fmt::format("{}", v);
  if (r.finite && !std::isfinite(v))
    refuse(f, fmt::format("{} is {}, not a finite number", label, shown));
  if (r.min && !(v >= *r.min))
    refuse(f, fmt::format("{} is {}, less than {}", label, shown, *r.min));
  if (!allows(r.allowed, v))
    refuse(f, fmt::format("{} is {}, not {}", label, shown, allowed_words(r.allowed)));
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : " x ") + w;
  return out;
}

std::string extent_text(const std::vector<hsize_t>& dims) {
  std::vector<std::string> words;
  for (const hsize_t d : dims) words.push_back(std::to_string(d));
  return dims.empty() ? "scalar" : joined(words);
}

/// The dataset's extents against its named dimensions: the bound ones must agree, the others
/// are bound here for the datasets after it.
void check_shape(const h5::File& f, const std::string& path, const std::vector<std::string>& names,
                 const std::vector<hsize_t>& dims, Dimensions& bound) {
  const bool all_bound = std::all_of(names.begin(), names.end(),
                                     [&](const std::string& n) { return bound.count(n) > 0; });
  std::string expected = joined(names);
  if (all_bound) {
    std::vector<hsize_t> want;
    for (const auto& n : names) want.push_back(bound[n]);
    expected += " = " + extent_text(want);
    hsize_t count = 1, wanted = 1;
    for (const hsize_t d : dims) count *= d;  // within the file's size: read before
    for (const hsize_t d : want) wanted *= d;
    if (count != wanted)
      refuse(f, fmt::format("dataset '{}' has {} values, expected {} ({})", path, count, wanted,
                            expected));
    if (dims != want)
      refuse(f, fmt::format("dataset '{}' has shape {}, expected {}", path, extent_text(dims),
                            expected));
    return;
  }
  if (dims.size() != names.size())
    refuse(f, fmt::format("dataset '{}' has shape {}, expected {}", path, extent_text(dims),
                          expected));
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto it = bound.find(names[k]);
    if (it == bound.end()) {
      bound[names[k]] = dims[k];
    } else if (it->second != dims[k]) {
      refuse(f, fmt::format("dataset '{}' has shape {}, expected {} with {} = {}", path,
                            extent_text(dims), expected, names[k], it->second));
    }
  }
}

void check_values(const h5::File& f, const std::string& path, const DatasetRule& r,
                  const std::vector<double>& values) {
  for (const double v : values) {
    if (r.whole && !whole_number(v, -kMaxExactWhole, kMaxExactWhole))
      refuse(f, fmt::format("dataset '{}' holds {}, not a whole number", path, v));
    if (r.finite && !std::isfinite(v))
      refuse(f, fmt::format("dataset '{}' holds {}, not a finite number", path, v));
    if (!std::isnan(v) && !allows(r.allowed, v))
      refuse(f, fmt::format("dataset '{}' holds {}, not {}", path, v, allowed_words(r.allowed)));
  }
}

void check_dataset(const h5::File& f, const std::string& group, const DatasetRule& r,
                   Dimensions& bound) {
  const std::string path = child(group, r.name);
  if (!f.has_dataset(path)) {
    if (needed(f, group, r.required, r.required_unless))
      refuse(f, fmt::format("dataset '{}' missing", path));
    return;
  }
  if (f.is_group(path)) refuse(f, fmt::format("dataset '{}' is a group", path));
  // Its class, that it is an array, written and within the file (h5::File's checks).
  const std::vector<double> values = f.read_float_dataset(path);
  check_shape(f, path, r.shape, f.dataset_shape(path), bound);
  check_values(f, path, r, values);
  if (f.has_attribute("units", path)) {
    const std::string unit = f.read_attribute_string("units", path);
    if (unit != r.unit)
      refuse(f, fmt::format("attribute 'units' of '{}' is '{}', not '{}'", path, unit, r.unit));
  }
}

void check_group(const h5::File& f, const std::string& object, const GroupRule& g) {
  for (const AttributeRule& a : g.attributes) check_attribute(f, object, a);
  if (!g.one_of.empty() &&
      std::none_of(g.one_of.begin(), g.one_of.end(),
                   [&](const std::string& name) { return f.has_dataset(child(object, name)); })) {
    std::vector<std::string> names;
    for (const auto& n : g.one_of) names.push_back("'" + n + "'");
    std::string words;
    for (std::size_t k = 0; k < names.size(); ++k)
      words += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
    refuse(f, fmt::format("group '{}' has none of the datasets {}", object, words));
  }
  Dimensions bound;  // each group instance binds its own
  for (const DatasetRule& d : g.datasets) check_dataset(f, object, d, bound);
}

}  // namespace schema_check

const std::vector<int>& stats_schema_versions() {
  return stats_schema().versions;
}

int current_stats_schema_version() {
  return stats_schema().current;
}

void check_stats_schema(const h5::File& f) {
  for (const GroupRule& g : stats_schema().groups) {
    for (const std::string& pattern : g.paths) {
      if (g.required) schema_check::check_required(f, pattern);
      for (const std::string& object : schema_check::instances(f, pattern))
        schema_check::check_group(f, object, g);
    }
  }
}

StatsFileSummary check_stats_file(const std::string& path) {
  const h5::File f = h5::File::open_read(path);
  check_stats_checksum(f, std::filesystem::path(path).parent_path().string());
  check_stats_schema(f);
  StatsFileSummary s;
  if (f.has_attribute("schema_version"))
    s.schema_version = static_cast<int>(f.read_attribute_int("schema_version"));
  s.campaign = f.read_attribute_string("campaign");
  s.ensembles = f.list_group("ensembles").size();
  return s;
}

}  // namespace jam::stats
