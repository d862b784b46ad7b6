#include "sim/io/open_run_limits.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "sim/io/open_run_limits_json.hpp"

namespace jam {
namespace {

double number(const nlohmann::json& table, const char* entry, const char* key) {
  const auto& e = table.at(entry);
  if (!e.contains(key) || !e.at(key).is_number())
    throw std::logic_error(std::string("open_run_limits.json: ") + entry + "." + key +
                           " is not a number");
  return e.at(key).get<double>();
}

std::int64_t whole(const nlohmann::json& table, const char* entry) {
  const auto& v = table.at(entry).at("value");
  if (!v.is_number_integer())
    throw std::logic_error(std::string("open_run_limits.json: ") + entry +
                           ".value is not an integer");
  return v.get<std::int64_t>();
}

OpenRunLimits parse() {
  const auto t = nlohmann::json::parse(kOpenRunLimitsJson);
  return OpenRunLimits{whole(t, "max_whole"),
                       whole(t, "max_points"),
                       number(t, "diameter_ratio", "min"),
                       number(t, "diameter_ratio", "max"),
                       number(t, "max_contacts_per_particle", "value"),
                       number(t, "jamming_packing_fraction", "above"),
                       number(t, "jamming_packing_fraction", "below"),
                       number(t, "phi_init_slack", "value"),
                       number(t, "rate_tolerance", "value")};
}

}  // namespace

const OpenRunLimits& open_run_limits() {
  static const OpenRunLimits limits = parse();
  return limits;
}

}  // namespace jam
