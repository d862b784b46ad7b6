#include "campaign/campaign_file.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>
#include <variant>

#include "campaign/check_names.hpp"
#include "campaign/run_plan.hpp"
#include "campaign/toml_file.hpp"
#include "campaign/toml_reader.hpp"
#include "sim/io/output_path.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/run_parameters.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {
namespace {

/// A campaign key of an integer parameter: the allowed values and the member's range are
/// checked before narrowing, so that 2^32 + 2 is not read as 2.
template <class T>
T integer_key(TableReader& r, const RunParameter& p, T fallback) {
  const std::int64_t v =
      r.integer(p.name, p.campaign == CampaignKey::required, static_cast<std::int64_t>(fallback));
  const std::string text = std::to_string(v);
  if (!p.choices.empty() &&
      std::find(p.choices.begin(), p.choices.end(), text) == p.choices.end()) {
    r.fail(p.name, fmt::format("{} (must be {})", v, or_list(p.choices)));
  }
  if (!std::in_range<T>(v)) r.fail(p.name, fmt::format("{} (out of range)", v));
  return static_cast<T>(v);
}

/// The per-run keys of a campaign: the campaign keys of the parameter table, by type.
void read_run_parameters(TableReader& r, SimConfig& run) {
  for (const RunParameter& p : run_parameters()) {
    if (p.campaign == CampaignKey::none) continue;
    const bool required = p.campaign == CampaignKey::required;
    std::visit(
        [&](auto member) {
          auto& target = run.*member;
          using T = std::decay_t<decltype(target)>;
          if constexpr (std::is_same_v<T, double>) {
            target = r.number(p.name, required, target);
          } else if constexpr (std::is_same_v<T, bool>) {
            target = r.boolean(p.name, target);
          } else if constexpr (std::is_same_v<T, std::string>) {
            target = p.choices.empty() ? r.text(p.name, required, target)
                                       : r.string(p.name, required, target);
          } else {
            target = integer_key<T>(r, p, target);
          }
        },
        p.field);
  }
}

/// chain_phi_init: one entry per rate; 0 starts that rate from its relaxed random start (the
/// fastest rate must), a packing phi'_init takes the next faster rate's configuration there.
/// A start lies above every phi_init and the faster rate's own start, below phi_stop, and on
/// the output grid (the faster run leaves it at an output point).
void validate_chain(TableReader& r, const Campaign& c) {
  if (c.chain_phi_init.empty()) return;
  const std::string key = "chain_phi_init";
  if (c.chain_phi_init.size() != c.log10_rates.size()) {
    r.fail(key, fmt::format("{} values for {} log10_rates (one per rate)", c.chain_phi_init.size(),
                            c.log10_rates.size()));
  }
  if (c.run.dynamics != "overdamped") r.fail(key, "chained starts are for overdamped dynamics");
  if (!c.run.relax) r.fail(key, "needs relax = true (the fastest rate's start is relaxed)");
  const double highest_phi_init = *std::max_element(c.phi_init.begin(), c.phi_init.end());
  double faster_start = highest_phi_init;
  const std::vector<std::size_t> order = rates_fastest_first(c);
  for (const std::size_t k : order) {
    const double phi = c.chain_phi_init[k];
    if (phi == 0.0) {
      faster_start = highest_phi_init;
      continue;
    }
    const auto rate = fmt::format("{:g} at log10 rate {:g}", phi, c.log10_rates[k]);
    // Starts read from another campaign (chain_starts_from) come from its faster rates.
    if (k == order.front() && c.chain_starts_from.empty()) {
      r.fail(key, rate + ": the fastest rate has no faster one to start from (give 0)");
    }
    if (!(phi > faster_start && phi < c.run.phi_stop)) {
      r.fail(key, fmt::format("{}: must lie above every phi_init and the faster rate's start "
                              "({:g}) and below phi_stop ({:g})",
                              rate, faster_start, c.run.phi_stop));
    }
    // On the grid to rounding only: a start a hair off a grid point (0.8000000001) would be
    // left at the next point instead, silently.
    const double grid = std::round(phi / c.run.phi_step) * c.run.phi_step;
    if (std::abs(phi - grid) > 1e-13 * phi) {  // within the 1e-12 margin of leave_chain_start
      r.fail(key, fmt::format("{:.15g} at log10 rate {:g}: must be a multiple of phi_step ({:g}), "
                              "such as {:.10g}",
                              phi, c.log10_rates[k], c.run.phi_step, grid));
    }
    faster_start = phi;
  }
}

/// [question] (CampaignQuestion): each key checked on its own, the error naming the key and
/// its value. The range must lie where the campaign compresses (above its lowest phi_init,
/// below phi_stop): a range no run reaches would only ever be "nothing to judge".
CampaignQuestion read_question(TableReader& r, const Campaign& c) {
  CampaignQuestion question;
  const toml::node* node = r.find("question", false);
  if (!node) return question;
  const toml::table* table = node->as_table();
  if (!table) r.fail("question", "must be a table ([question])");
  TableReader t(*table, r.path(), "question");
  auto packing = [&t](const char* key) -> std::optional<double> {
    if (!t.find(key, false)) return std::nullopt;
    const double v = t.number(key, false, NAN);
    if (!(v > 0 && v < 1)) t.fail(key, fmt::format("{:g}: must be a packing in (0, 1)", v));
    return v;
  };
  question.phi_min = packing("phi_min");
  question.phi_max = packing("phi_max");
  if (question.phi_min.has_value() != question.phi_max.has_value()) {
    const char* missing = question.phi_min ? "phi_max" : "phi_min";
    t.fail(missing, "missing: phi_min and phi_max state the range judged together");
  }
  if (question.states_range()) {
    if (!(*question.phi_min < *question.phi_max))
      t.fail("phi_max",
             fmt::format("{:g}: must exceed phi_min = {:g}", *question.phi_max, *question.phi_min));
    if (!(*question.phi_min < c.run.phi_stop))
      t.fail("phi_min", fmt::format("{:g}: must lie below phi_stop = {:g} (no run reaches it)",
                                    *question.phi_min, c.run.phi_stop));
    const double lowest = *std::min_element(c.phi_init.begin(), c.phi_init.end());
    if (!(*question.phi_max > lowest))
      t.fail("phi_max", fmt::format("{:g}: must lie above the lowest phi_init = {:g} (no run is "
                                    "compressed there)",
                                    *question.phi_max, lowest));
  }
  question.checks = t.strings("checks");
  const std::vector<std::string> known = question_check_names();
  std::set<std::string> seen;
  for (const auto& name : question.checks) {
    if (std::find(known.begin(), known.end(), name) == known.end())
      t.fail("checks",
             fmt::format("'{}': unknown check (one of {})", name, fmt::join(known, ", ")));
    if (!seen.insert(name).second) t.fail("checks", fmt::format("'{}': repeated", name));
  }
  if (t.find("alpha", false)) {
    const double a = t.number("alpha", false, NAN);
    if (!(a > 0 && a < 0.5)) t.fail("alpha", fmt::format("{:g}: must be in (0, 0.5)", a));
    question.alpha = a;
  }
  t.reject_unknown_keys();
  return question;
}

}  // namespace

/// Every registered check's name: the [margins] keys.
static std::set<std::string> registered_check_names() {
  std::set<std::string> out;
  for (const auto& c : kRegisteredCheckNames) out.emplace(c.name);
  return out;
}

std::vector<std::string> question_check_names() {
  std::vector<std::string> names;
  // The registry's names (campaign/check_names.hpp, generated from it): the members of `all`,
  // and every check of this campaign's own data or of LAMMPS that `all` leaves out unless asked
  // (the question is one way to ask for it); not those that need another campaign's.
  for (const auto& c : kRegisteredCheckNames)
    if (c.in_all || c.kind == "stats" || c.kind == "lammps") names.emplace_back(c.name);
  names.emplace_back("compare");
  return names;
}

std::vector<std::size_t> rates_fastest_first(const Campaign& c) {
  std::vector<std::size_t> order(c.log10_rates.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&c](std::size_t a, std::size_t b) {
    return c.log10_rates[a] > c.log10_rates[b];
  });
  return order;
}

SimConfig campaign_run_defaults() {
  SimConfig s;
  s.relax_energy = "1e-14";
  s.quiet = true;
  return s;
}

Campaign parse_campaign(const std::string& text, const std::string& path) {
  // Plain ASCII only: the TOML parser of Debian 12 (toml++ 3.3.0) reaches undefined behaviour
  // on some non-ASCII characters (marzer/tomlplusplus#295, found here by fuzzing), and no key
  // or value of a campaign needs one.
  if (const auto bad = first_non_ascii(text)) {
    throw CampaignError(fmt::format("{}:{}: byte 0x{:02x}: campaign files are plain ASCII text",
                                    path, bad->line, bad->byte));
  }
  toml::table table;
  try {
    table = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw CampaignError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
  }
  TableReader r(table, path);
  Campaign c;
  c.source_path = path;
  c.source_text = text;
  c.name = r.string("name", true, "");
  read_run_parameters(r, c.run);
  c.sizes = r.integers("sizes");
  c.phi_init = r.numbers("phi_init");
  c.log10_rates = r.numbers("log10_rates");
  c.chain_phi_init = r.optional_numbers("chain_phi_init");
  c.chain_starts_from = r.string("chain_starts_from", false, "");
  c.samples = r.integer("samples", true, 0);
  c.first_sample = r.integer("first_sample", false, c.first_sample);
  const std::int64_t seed = r.integer("seed", true, 0);
  c.output = r.string("output", true, "");
  c.margins = r.number_table("margins", registered_check_names());
  c.regions = r.number_table("regions", {"phi_j", "near", "far"}, "key");
  if (c.regions.count("phi_j") && !(c.regions.at("phi_j") < 1))
    r.fail("regions",
           fmt::format("phi_j = {:g}: must be a packing in (0, 1)", c.regions.at("phi_j")));
  if (c.regions.count("near") && c.regions.count("far") &&
      !(c.regions.at("near") < c.regions.at("far")))
    r.fail("regions", fmt::format("far = {:g}: must exceed near = {:g}", c.regions.at("far"),
                                  c.regions.at("near")));
  c.question = read_question(r, c);
  c.expected_failures = r.strings("expected_failures");
  c.compare_with = r.strings("compare_with");
  for (const auto& d : c.compare_with)
    if (d.empty()) r.fail("compare_with", "'': must name campaign directories");
  for (const auto& e : c.expected_failures) {
    if (e.find(": ") == std::string::npos || e.find(": ") == 0) {
      r.fail("expected_failures", fmt::format("'{}': must read 'check: part of the case name'", e));
    }
  }
  r.reject_unknown_keys();

  if (c.name.empty() || c.name.find_first_of("/ \t") != std::string::npos || c.name == "." ||
      c.name == "..") {
    r.fail("name", fmt::format("'{}': must be a non-empty word, not . or .. (it names the report)",
                               c.name));
  }
  for (auto n : c.sizes) {
    if (n < 2 || n % 2 != 0) r.fail("sizes", fmt::format("{} (each must be even and >= 2)", n));
    if (n > (std::int64_t{1} << 31)) r.fail("sizes", fmt::format("{} (at most 2^31)", n));
  }
  for (double phi : c.phi_init) {
    if (!(phi > 0.0 && phi < c.run.phi_stop)) {
      r.fail("phi_init",
             fmt::format("{:g} (each must be in (0, phi_stop = {:g}))", phi, c.run.phi_stop));
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
  // A plan holds every run in memory (about 1 kB each): a bound checked before planning.
  const double runs = static_cast<double>(c.samples) * static_cast<double>(c.sizes.size()) *
                      static_cast<double>(c.phi_init.size()) *
                      static_cast<double>(c.log10_rates.size());
  if (runs > static_cast<double>(kMaxCampaignRuns)) {
    r.fail("samples", fmt::format("{} x {} sizes x {} phi_init x {} rates = {:.3g} runs (at most "
                                  "{} per campaign file; split it with first_sample)",
                                  c.samples, c.sizes.size(), c.phi_init.size(),
                                  c.log10_rates.size(), runs, kMaxCampaignRuns));
  }
  c.base_seed = static_cast<std::uint64_t>(seed);
  if (c.output.empty()) r.fail("output", "must name a directory");
  if (c.run.checkpoint_interval < 0.0) r.fail("checkpoint_interval", "must be >= 0 seconds");
  validate_chain(r, c);
  if (!c.chain_starts_from.empty() &&
      std::filesystem::path(c.chain_starts_from).lexically_normal() ==
          std::filesystem::path(c.output).lexically_normal()) {
    r.fail("chain_starts_from", "'" + c.chain_starts_from + "': is this campaign's own output");
  }
  if (!c.chain_starts_from.empty() && c.chain_phi_init.empty()) {
    r.fail("chain_starts_from",
           "'" + c.chain_starts_from +
               "': needs chain_phi_init, the packings at which that campaign's starts are taken");
  }

  // Everything a single run checks, with the campaign's key names in the message: every size
  // and start (a size too small for its box, say), and every rate.
  try {
    for (const std::int64_t n : c.sizes) {
      for (const double phi : c.phi_init) {
        for (const double lr : c.log10_rates) {
          SimConfig probe = run_config(c, n, phi, lr, 0);
          probe.out = "probe";
          validate(probe);
          validate_generated_box(probe);
        }
      }
    }
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    if (message.rfind("--n ", 0) == 0) r.fail("sizes", message.substr(4));
    for (const RunParameter& p : run_parameters()) {
      const std::string option = p.option() + " ";
      if (p.campaign != CampaignKey::none && message.rfind(option, 0) == 0) {
        r.fail(p.name, message.substr(option.size()));
      }
    }
    throw CampaignError(fmt::format("{}: {}", path, message));
  }
  return c;
}

Campaign read_campaign(const std::string& path) {
  try {
    check_input_file("campaign file", path);
  } catch (const std::runtime_error& e) {
    throw CampaignError(e.what());
  }
  std::ifstream in(path);
  if (!in) throw CampaignError(fmt::format("{}: cannot read campaign file", path));
  std::stringstream text;
  text << in.rdbuf();
  return parse_campaign(text.str(), path);
}

std::vector<std::pair<std::string, std::string>> identity_keys(const Campaign& c) {
  std::vector<std::pair<std::string, std::string>> keys;
  for (const RunParameter& p : run_parameters()) {
    if (p.campaign == CampaignKey::none || !p.in_fingerprint()) continue;
    // As written in the file (relax_energy "auto" stays "auto"); a Q the dynamics ignores is "-".
    const bool ignored = p.inertial_only && c.run.dynamics != "inertial";
    keys.emplace_back(p.name, ignored ? "-" : fingerprint_text(field_value(c.run, p)));
  }
  keys.emplace_back("seed", std::to_string(c.base_seed));
  keys.emplace_back("chain_starts_from", c.chain_starts_from.empty() ? "-" : c.chain_starts_from);
  return keys;
}

}  // namespace jam
