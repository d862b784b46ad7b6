#include "checks/verdict_schema.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <stdexcept>

#include "checks/verdict_schema_text.hpp"

namespace jam::checks {
namespace {

using nlohmann::json;

/// A value in a message: its JSON, at most 60 characters (as jamio shows it).
std::string shown(const json& v) {
  const std::string text = v.dump();
  return text.size() <= 60 ? text : text.substr(0, 57) + "...";
}

/// The words after "not" for a type.
std::string type_words(const std::string& type) {
  if (type == "string") return "a string";
  if (type == "number") return "a number";
  if (type == "integer") return "a whole number";
  if (type == "boolean") return "true or false";
  if (type == "object") return "an object";
  if (type == "array") return "an array";
  throw std::logic_error("reference/schema/checks.toml: unknown type " + type);
}

bool of_type(const json& v, const std::string& type) {
  if (type == "string") return v.is_string();
  if (type == "number") return v.is_number();  // never a boolean in nlohmann::json
  if (type == "integer") return v.is_number_integer();
  if (type == "boolean") return v.is_boolean();
  if (type == "object") return v.is_object();
  if (type == "array") return v.is_array();
  return false;
}

json toml_value(const toml::node& n) {
  if (const auto s = n.value<std::string>(); s && n.is_string()) return *s;
  if (n.is_integer()) return *n.value<std::int64_t>();
  if (n.is_floating_point()) return *n.value<double>();
  throw std::logic_error("reference/schema/checks.toml: an allowed value of another type");
}

std::vector<SchemaField> fields_of(const toml::table& root, const char* name) {
  const toml::table* t = root[name].as_table();
  if (!t) throw std::logic_error(fmt::format("reference/schema/checks.toml: no [{}]", name));
  std::vector<SchemaField> out;
  for (const auto& [key, node] : *t) {
    const toml::table* f = node.as_table();
    if (!f)
      throw std::logic_error(fmt::format("reference/schema/checks.toml: {}.{}", name, key.str()));
    SchemaField s;
    s.name = std::string(key.str());
    s.type = (*f)["type"].value_or(std::string());
    type_words(s.type);  // a type the rules know
    s.required = (*f)["required"].value_or(false);
    s.null = (*f)["null"].value_or(false);
    s.entries = (*f)["entries"].value_or(std::string());
    s.entries_null = (*f)["entries_null"].value_or(false);
    s.fields = (*f)["fields"].value_or(std::string());
    if (const toml::array* a = (*f)["allowed"].as_array())
      for (const auto& v : *a) s.allowed.push_back(toml_value(v));
    out.push_back(std::move(s));
  }
  return out;
}

VerdictSchema parse_schema() {
  const toml::table root = toml::parse(kVerdictSchemaToml);
  VerdictSchema s;
  if (const toml::array* v = root["file"]["versions"].as_array())
    for (const auto& x : *v) s.versions.push_back(static_cast<int>(x.value_or(std::int64_t{0})));
  s.current = static_cast<int>(root["file"]["current"].value_or(std::int64_t{0}));
  s.object = fields_of(root, "object");
  s.verdict = fields_of(root, "verdict");
  s.table = fields_of(root, "table");
  return s;
}

std::string allowed_words(const std::vector<json>& allowed) {
  std::string out;
  for (const auto& a : allowed) out += (out.empty() ? "" : ", ") + a.dump();
  return out;
}

[[noreturn]] void refuse(const std::string& field, const json& v, const std::string& words) {
  throw std::runtime_error(fmt::format("field '{}' is {}, not {}", field, shown(v), words));
}

}  // namespace

const std::vector<SchemaField>& VerdictSchema::named(const std::string& name) const {
  if (name == "object") return object;
  if (name == "verdict") return verdict;
  if (name == "table") return table;
  throw std::logic_error("reference/schema/checks.toml: no table " + name);
}

const VerdictSchema& verdict_schema() {
  static const VerdictSchema schema = parse_schema();
  return schema;
}

void check_fields(const json& j, const std::string& table_name, const std::string& prefix) {
  for (const SchemaField& f : verdict_schema().named(table_name)) {
    const std::string field = prefix + f.name;
    if (!j.contains(f.name)) {
      if (f.required) throw std::runtime_error(fmt::format("field '{}' missing", field));
      continue;
    }
    const json& v = j.at(f.name);
    if (v.is_null() && f.null) continue;
    if (!of_type(v, f.type)) refuse(field, v, type_words(f.type));
    if (!f.allowed.empty() && std::find(f.allowed.begin(), f.allowed.end(), v) == f.allowed.end())
      refuse(field, v, "one of " + allowed_words(f.allowed));
    if (!f.entries.empty())
      for (const auto& [key, x] : v.items())
        if (!(x.is_null() && f.entries_null) && !of_type(x, f.entries))
          refuse(field + "." + key, x, type_words(f.entries));
    if (!f.fields.empty()) check_fields(v, f.fields, field + ".");
  }
}

const json& checked_verdicts(const json& file) {
  const VerdictSchema& s = verdict_schema();
  auto reads = [&s](int version) {
    return std::find(s.versions.begin(), s.versions.end(), version) != s.versions.end();
  };
  const json* verdicts = nullptr;
  if (file.is_array() && reads(1)) {
    verdicts = &file;
  } else if (file.is_object() && file.contains("verdicts") && file["verdicts"].is_array()) {
    check_fields(file, "object");
    verdicts = &file["verdicts"];
  } else {
    throw std::runtime_error("neither an array of verdicts nor an object with a 'verdicts' array");
  }
  for (std::size_t k = 0; k < verdicts->size(); ++k) {
    const json& v = (*verdicts)[k];
    try {
      if (!v.is_object()) throw std::runtime_error(fmt::format("is {}, not an object", shown(v)));
      check_fields(v, "verdict");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("verdict {}: {}", k, e.what()));
    }
  }
  return *verdicts;
}

}  // namespace jam::checks
