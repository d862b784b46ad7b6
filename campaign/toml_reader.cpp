#include "campaign/toml_reader.hpp"

#include <fmt/format.h>

#include <cmath>

#include "campaign/campaign_file.hpp"
#include "campaign/toml_file.hpp"

namespace jam {

void TableReader::fail(const std::string& key, const std::string& what) const {
  const toml::node* node = table_.get(key);
  const auto line = node ? node->source().begin.line : 0u;
  const std::string name = prefix_.empty() ? key : prefix_ + "." + key;
  if (line > 0) throw CampaignError(fmt::format("{}:{}: {}: {}", path_, line, name, what));
  throw CampaignError(fmt::format("{}: {}: {}", path_, name, what));
}

const toml::node* TableReader::find(const std::string& key, bool required) {
  seen_.insert(key);
  const toml::node* node = table_.get(key);
  if (!node && required) fail(key, "missing (required)");
  return node;
}

double TableReader::number(const std::string& key, bool required, double fallback) {
  const toml::node* node = find(key, required);
  if (!node) return fallback;
  if (!node->is_number()) fail(key, "must be a number");
  const double v = *toml_number(node);
  if (!std::isfinite(v)) fail(key, "must be finite");
  return v;
}

std::int64_t TableReader::integer(const std::string& key, bool required, std::int64_t fallback) {
  const toml::node* node = find(key, required);
  if (!node) return fallback;
  if (!node->is_integer()) fail(key, "must be an integer");
  return node->value<std::int64_t>().value();
}

std::string TableReader::string(const std::string& key, bool required,
                                const std::string& fallback) {
  const toml::node* node = find(key, required);
  if (!node) return fallback;
  if (!node->is_string()) fail(key, "must be a string");
  return printable(key, node->value<std::string>().value());
}

std::string TableReader::printable(const std::string& key, const std::string& v) const {
  for (const char ch : v) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte < 0x20 || byte >= 0x7f) {
      fail(key, fmt::format("a string with the character 0x{:02x} (escapes must give printable "
                            "ASCII)",
                            byte));
    }
  }
  if (v.size() > 4096) fail(key, fmt::format("a string of {} characters (at most 4096)", v.size()));
  return v;
}

std::string TableReader::text(const std::string& key, bool required, const std::string& fallback) {
  const toml::node* node = find(key, required);
  if (node && node->is_number()) return fmt::format("{:.17g}", *toml_number(node));
  return string(key, required, fallback);
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  const toml::node* node = find(key, false);
  if (!node) return fallback;
  if (!node->is_boolean()) fail(key, "must be true or false");
  return node->value<bool>().value();
}

std::vector<double> TableReader::numbers(const std::string& key) {
  const std::vector<double> v = number_array(key, true, "must be a non-empty array of numbers");
  if (v.empty()) fail(key, "must be a non-empty array of numbers");
  if (std::set<double>(v.begin(), v.end()).size() != v.size()) fail(key, "repeated value");
  return v;
}

std::vector<std::int64_t> TableReader::integers(const std::string& key) {
  const toml::node* node = find(key, true);
  const toml::array* array = node->as_array();
  if (!array || array->empty()) fail(key, "must be a non-empty array of integers");
  std::vector<std::int64_t> v;
  for (const auto& element : *array) {
    if (!element.is_integer()) fail(key, "must be a non-empty array of integers");
    v.push_back(element.value<std::int64_t>().value());
  }
  if (std::set<std::int64_t>(v.begin(), v.end()).size() != v.size()) fail(key, "repeated value");
  return v;
}

std::map<std::string, double> TableReader::number_table(const std::string& key,
                                                        const std::set<std::string>& allowed,
                                                        const char* what) {
  std::map<std::string, double> out;
  const toml::node* node = find(key, false);
  if (!node) return out;
  const toml::table* table = node->as_table();
  if (!table) fail(key, "must be a table of numbers");
  for (const auto& [name, value] : *table) {
    const std::string k(name.str());
    if (!allowed.count(k)) fail(key, fmt::format("{}: unknown {}", k, what));
    if (!value.is_number()) fail(key, fmt::format("{}: must be a number", k));
    const double v = *toml_number(&value);
    if (!std::isfinite(v) || v <= 0) fail(key, fmt::format("{} = {}: must be > 0", k, v));
    out[k] = v;
  }
  return out;
}

std::vector<double> TableReader::optional_numbers(const std::string& key) {
  return number_array(key, false, "must be an array of numbers");
}

std::vector<double> TableReader::number_array(const std::string& key, bool required,
                                              const char* shape) {
  std::vector<double> v;
  const toml::node* node = find(key, required);
  if (!node) return v;
  const toml::array* array = node->as_array();
  if (!array) fail(key, shape);
  for (const auto& element : *array) {
    if (!element.is_number()) fail(key, shape);
    v.push_back(*toml_number(&element));
    if (!std::isfinite(v.back())) fail(key, "values must be finite");
  }
  return v;
}

std::vector<std::string> TableReader::strings(const std::string& key) {
  std::vector<std::string> out;
  const toml::node* node = find(key, false);
  if (!node) return out;
  const toml::array* array = node->as_array();
  if (!array) fail(key, "must be an array of strings");
  for (const auto& element : *array) {
    if (!element.is_string()) fail(key, "must be an array of strings");
    out.push_back(printable(key, element.value<std::string>().value()));
  }
  return out;
}

void TableReader::reject_unknown_keys() const {
  for (const auto& [key, node] : table_) {
    if (!seen_.count(std::string(key.str()))) {
      throw CampaignError(fmt::format("{}:{}: {}{}: unknown key", path_, node.source().begin.line,
                                      prefix_.empty() ? "" : prefix_ + ".", key.str()));
    }
  }
}

}  // namespace jam
