#include "stats/stats_schema_rules.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <stdexcept>

#include "stats/stats_schema_text.hpp"

namespace jam::stats {
namespace schema_rules {

[[noreturn]] void bad_schema(const std::string& what) {
  throw std::logic_error("reference/schema/stats.toml: " + what);
}

std::vector<std::string> strings_of(const toml::node_view<const toml::node>& node) {
  std::vector<std::string> out;
  if (const toml::array* a = node.as_array())
    for (const auto& v : *a) out.push_back(v.value_or(std::string()));
  return out;
}

std::vector<AllowedValue> allowed_of(const toml::table& t) {
  std::vector<AllowedValue> out;
  if (const toml::array* a = t["allowed"].as_array()) {
    for (const auto& v : *a) {
      if (v.is_string()) {
        out.push_back({true, 0, *v.value<std::string>()});
      } else if (v.is_number()) {
        out.push_back({false, *v.value<double>(), ""});
      } else {
        bad_schema("an allowed value neither a number nor a string");
      }
    }
  }
  return out;
}

const toml::table& table_of(const toml::node& node, const std::string& where) {
  const toml::table* t = node.as_table();
  if (!t) bad_schema(where + " is not a table");
  return *t;
}

AttributeRule attribute_rule(const toml::table& t) {
  AttributeRule r;
  r.name = t["name"].value_or(std::string());
  r.type = t["type"].value_or(std::string());
  if (r.type != "integer" && r.type != "float" && r.type != "string")
    bad_schema(fmt::format("attribute '{}' of unknown type '{}'", r.name, r.type));
  r.required = t["required"].value_or(false);
  r.required_unless = t["required_unless"].value_or(std::string());
  r.allowed = allowed_of(t);
  if (const auto min = t["min"].value<double>()) r.min = *min;
  r.finite = t["finite"].value_or(false);
  return r;
}

DatasetRule dataset_rule(const toml::table& t) {
  DatasetRule r;
  r.name = t["name"].value_or(std::string());
  r.type = t["type"].value_or(std::string());
  if (r.type != "float") bad_schema(fmt::format("dataset '{}' of type '{}'", r.name, r.type));
  r.shape = strings_of(t["shape"]);
  if (r.shape.empty()) bad_schema(fmt::format("dataset '{}' without a shape", r.name));
  r.unit = t["unit"].value_or(std::string());
  r.required = t["required"].value_or(false);
  r.required_unless = t["required_unless"].value_or(std::string());
  r.finite = t["finite"].value_or(false);
  r.whole = t["whole"].value_or(false);
  r.allowed = allowed_of(t);
  return r;
}

/// The attributes and datasets of `t` (a [[group]] or a [sets.NAME]) appended to g.
void add_rules(GroupRule& g, const toml::table& t) {
  if (const toml::array* a = t["attributes"].as_array())
    for (const auto& x : *a) g.attributes.push_back(attribute_rule(table_of(x, "an attribute")));
  if (const toml::array* a = t["datasets"].as_array())
    for (const auto& x : *a) g.datasets.push_back(dataset_rule(table_of(x, "a dataset")));
}

StatsSchema parse() {
  const toml::table root = toml::parse(kStatsSchemaToml);
  StatsSchema s;
  if (const toml::array* v = root["file"]["versions"].as_array())
    for (const auto& x : *v) s.versions.push_back(static_cast<int>(x.value_or(std::int64_t{0})));
  s.current = static_cast<int>(root["file"]["current"].value_or(std::int64_t{0}));
  const toml::array* groups = root["group"].as_array();
  if (!groups) bad_schema("no [[group]]");
  for (const auto& node : *groups) {
    const toml::table& t = table_of(node, "a [[group]]");
    GroupRule g;
    g.paths = strings_of(t["paths"]);
    g.required = t["required"].value_or(false);
    g.one_of = strings_of(t["one_of"]);
    // A set's rules come first, then the group's own (jamio takes them in the same order).
    for (const std::string& set : strings_of(t["include"])) {
      const toml::node* included = root["sets"][set].node();
      if (!included) bad_schema("no [sets." + set + "]");
      add_rules(g, table_of(*included, "[sets." + set + "]"));
    }
    add_rules(g, t);
    s.groups.push_back(std::move(g));
  }
  return s;
}

}  // namespace schema_rules

const StatsSchema& stats_schema() {
  static const StatsSchema schema = schema_rules::parse();
  return schema;
}

}  // namespace jam::stats
