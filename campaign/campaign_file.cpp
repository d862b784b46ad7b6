#include "campaign/campaign_file.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "campaign/run_plan.hpp"
#include "checks/check_registry.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {
namespace {

class Reader {
 public:
  Reader(const toml::table& table, std::string path) : table_(table), path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    const toml::node* node = table_.get(key);
    const auto line = node ? node->source().begin.line : 0u;
    if (line > 0) throw CampaignError(fmt::format("{}:{}: {}: {}", path_, line, key, what));
    throw CampaignError(fmt::format("{}: {}: {}", path_, key, what));
  }

  const toml::node* find(const std::string& key, bool required) {
    seen_.insert(key);
    const toml::node* node = table_.get(key);
    if (!node && required) fail(key, "missing (required)");
    return node;
  }

  double number(const std::string& key, bool required, double fallback) {
    const toml::node* node = find(key, required);
    if (!node) return fallback;
    if (!node->is_number()) fail(key, "must be a number");
    const double v = node->value<double>().value();
    if (!std::isfinite(v)) fail(key, "must be finite");
    return v;
  }

  std::int64_t integer(const std::string& key, bool required, std::int64_t fallback) {
    const toml::node* node = find(key, required);
    if (!node) return fallback;
    if (!node->is_integer()) fail(key, "must be an integer");
    return node->value<std::int64_t>().value();
  }

  std::string string(const std::string& key, bool required, const std::string& fallback) {
    const toml::node* node = find(key, required);
    if (!node) return fallback;
    if (!node->is_string()) fail(key, "must be a string");
    return node->value<std::string>().value();
  }

  bool boolean(const std::string& key, bool fallback) {
    const toml::node* node = find(key, false);
    if (!node) return fallback;
    if (!node->is_boolean()) fail(key, "must be true or false");
    return node->value<bool>().value();
  }

  std::vector<double> numbers(const std::string& key) {
    const toml::node* node = find(key, true);
    const toml::array* array = node->as_array();
    if (!array || array->empty()) fail(key, "must be a non-empty array of numbers");
    std::vector<double> v;
    for (const auto& element : *array) {
      if (!element.is_number()) fail(key, "must be a non-empty array of numbers");
      v.push_back(element.value<double>().value());
      if (!std::isfinite(v.back())) fail(key, "values must be finite");
    }
    if (std::set<double>(v.begin(), v.end()).size() != v.size()) fail(key, "repeated value");
    return v;
  }

  std::vector<std::int64_t> integers(const std::string& key) {
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

  /// An optional table of positive finite numbers, keys from `allowed`.
  std::map<std::string, double> number_table(const std::string& key,
                                             const std::set<std::string>& allowed) {
    std::map<std::string, double> out;
    const toml::node* node = find(key, false);
    if (!node) return out;
    const toml::table* table = node->as_table();
    if (!table) fail(key, "must be a table of numbers");
    for (const auto& [name, value] : *table) {
      const std::string k(name.str());
      if (!allowed.count(k)) fail(key, fmt::format("{}: unknown check", k));
      if (!value.is_number()) fail(key, fmt::format("{}: must be a number", k));
      const double v = value.value<double>().value();
      if (!std::isfinite(v) || v <= 0) fail(key, fmt::format("{} = {}: must be > 0", k, v));
      out[k] = v;
    }
    return out;
  }

  /// An optional array of strings.
  std::vector<std::string> strings(const std::string& key) {
    std::vector<std::string> out;
    const toml::node* node = find(key, false);
    if (!node) return out;
    const toml::array* array = node->as_array();
    if (!array) fail(key, "must be an array of strings");
    for (const auto& element : *array) {
      if (!element.is_string()) fail(key, "must be an array of strings");
      out.push_back(element.value<std::string>().value());
    }
    return out;
  }

  void reject_unknown_keys() const {
    for (const auto& [key, node] : table_) {
      if (!seen_.count(std::string(key.str()))) {
        throw CampaignError(
            fmt::format("{}:{}: {}: unknown key", path_, node.source().begin.line, key.str()));
      }
    }
  }

 private:
  const toml::table& table_;
  std::string path_;
  std::set<std::string> seen_;
};

}  // namespace

Campaign parse_campaign(const std::string& text, const std::string& path) {
  // Plain ASCII only: the TOML parser of Debian 12 (toml++ 3.3.0) reaches undefined behaviour
  // on some non-ASCII characters (marzer/tomlplusplus#295, found here by fuzzing), and no key
  // or value of a campaign needs one.
  int line = 1;
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte == '\n') ++line;
    if (byte >= 0x80 || (byte < 0x20 && byte != '\n' && byte != '\t' && byte != '\r') ||
        byte == 0x7f) {
      throw CampaignError(fmt::format("{}:{}: byte 0x{:02x}: campaign files are plain ASCII text",
                                      path, line, byte));
    }
  }
  toml::table table;
  try {
    table = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw CampaignError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  }
  Reader r(table, path);
  Campaign c;
  c.source_path = path;
  c.source_text = text;
  c.name = r.string("name", true, "");
  const std::int64_t dim = r.integer("dim", true, 2);
  if (dim != 2 && dim != 3) r.fail("dim", fmt::format("{} (must be 2 or 3)", dim));
  c.dim = static_cast<int>(dim);
  c.sizes = r.integers("sizes");
  c.phi_init = r.numbers("phi_init");
  c.log10_rates = r.numbers("log10_rates");
  c.samples = r.integer("samples", true, 0);
  c.first_sample = r.integer("first_sample", false, c.first_sample);
  c.phi_stop = r.number("phi_stop", true, 0.0);
  c.phi_step = r.number("phi_step", false, c.phi_step);
  c.dynamics = r.string("dynamics", false, c.dynamics);
  c.integrator = r.string("integrator", false, c.integrator);
  c.dt = r.number("dt", false, c.dt);
  c.q = r.number("q", false, c.q);
  const std::int64_t seed = r.integer("seed", true, 0);
  c.output = r.string("output", true, "");
  c.skin = r.number("skin", false, c.skin);
  c.diameter_ratio = r.number("diameter_ratio", false, c.diameter_ratio);
  c.relax = r.boolean("relax", c.relax);
  c.relax_energy = r.string("relax_energy", false, c.relax_energy);
  c.relax_time_max = r.number("relax_time_max", false, c.relax_time_max);
  c.rattlers = r.boolean("rattlers", c.rattlers);
  c.stress = r.boolean("stress", c.stress);
  c.jamming_point = r.boolean("jamming_point", c.jamming_point);
  c.checkpoint_interval = r.number("checkpoint_interval", false, c.checkpoint_interval);
  c.margins = r.number_table("margins", checks::check_names());
  c.expected_failures = r.strings("expected_failures");
  for (const auto& e : c.expected_failures) {
    if (e.find(": ") == std::string::npos || e.find(": ") == 0) {
      r.fail("expected_failures", fmt::format("'{}': must read 'check: part of the case name'", e));
    }
  }
  r.reject_unknown_keys();

  if (c.name.empty() || c.name.find_first_of("/ \t") != std::string::npos) {
    r.fail("name", "must be a non-empty word (it names the report)");
  }
  if (c.dim != 2 && c.dim != 3) r.fail("dim", fmt::format("{} (must be 2 or 3)", c.dim));
  for (auto n : c.sizes) {
    if (n < 2 || n % 2 != 0) r.fail("sizes", fmt::format("{} (each must be even and >= 2)", n));
    if (n > (std::int64_t{1} << 31)) r.fail("sizes", fmt::format("{} (at most 2^31)", n));
  }
  for (double phi : c.phi_init) {
    if (!(phi > 0.0 && phi < c.phi_stop)) {
      r.fail("phi_init",
             fmt::format("{:g} (each must be in (0, phi_stop = {:g}))", phi, c.phi_stop));
    }
  }
  for (double lr : c.log10_rates) {
    if (lr > 0.0 || lr < -12.0)
      r.fail("log10_rates", fmt::format("{:g} (must be in [-12, 0])", lr));
  }
  if (c.samples < 1 || c.samples > 1000000) {
    r.fail("samples", fmt::format("{} (must be in [1, 10^6])", c.samples));
  }
  if (c.first_sample < 0 || c.first_sample > 1000000) {
    r.fail("first_sample", fmt::format("{} (must be in [0, 10^6])", c.first_sample));
  }
  if (seed < 0) r.fail("seed", fmt::format("{} (must be >= 0)", seed));
  c.seed = static_cast<std::uint64_t>(seed);
  if (c.output.empty()) r.fail("output", "must name a directory");
  if (c.checkpoint_interval < 0.0) r.fail("checkpoint_interval", "must be >= 0 seconds");

  // Everything a single run checks, with the campaign's key names in the message.
  const std::map<std::string, std::string> option_to_key = {{"--phi-stop", "phi_stop"},
                                                            {"--phi-step", "phi_step"},
                                                            {"--dt", "dt"},
                                                            {"--dynamics", "dynamics"},
                                                            {"--integrator", "integrator"},
                                                            {"--q", "q"},
                                                            {"--skin", "skin"},
                                                            {"--diameter-ratio", "diameter_ratio"},
                                                            {"--relax-energy", "relax_energy"},
                                                            {"--relax-time-max", "relax_time_max"}};
  SimConfig probe = run_config(c, c.sizes.front(), c.phi_init.front(), c.log10_rates.front(), 0);
  probe.out = "probe";
  try {
    validate(probe);
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    for (const auto& [option, key] : option_to_key) {
      if (message.rfind(option + " ", 0) == 0) r.fail(key, message.substr(option.size() + 1));
    }
    throw CampaignError(fmt::format("{}: {}", path, message));
  }
  return c;
}

Campaign read_campaign(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw CampaignError(fmt::format("{}: cannot read campaign file", path));
  std::stringstream text;
  text << in.rdbuf();
  return parse_campaign(text.str(), path);
}

std::vector<std::pair<std::string, std::string>> identity_keys(const Campaign& c) {
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  return {{"dim", std::to_string(c.dim)},
          {"phi_stop", g(c.phi_stop)},
          {"phi_step", g(c.phi_step)},
          {"dynamics", c.dynamics},
          {"integrator", c.integrator},
          {"dt", g(c.dt)},
          {"q", c.dynamics == "inertial" ? g(c.q) : "-"},
          {"seed", std::to_string(c.seed)},
          {"skin", g(c.skin)},
          {"diameter_ratio", g(c.diameter_ratio)},
          {"relax", c.relax ? "true" : "false"},
          {"relax_energy", c.relax_energy},
          {"relax_time_max", g(c.relax_time_max)},
          {"rattlers", c.rattlers ? "true" : "false"},
          {"stress", c.stress ? "true" : "false"},
          {"jamming_point", c.jamming_point ? "true" : "false"}};
}

}  // namespace jam
