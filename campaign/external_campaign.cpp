#include "campaign/external_campaign.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "campaign/import_store.hpp"
#include "campaign/toml_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/terminal_text.hpp"
#include "sim/io/whole_number.hpp"

namespace fs = std::filesystem;

namespace jam {
namespace {

constexpr const char* kFile = "external.toml";
constexpr const char* kUnlisted =
    "not in external.toml, so not averaged (an import adopts it only when it is a copy of the "
    "file imported under its name; else move it away)";

std::string text_of(const toml::table& t, const char* key, const std::string& where) {
  const auto v = t[key].value<std::string>();
  if (!v) throw std::runtime_error(fmt::format("{}: missing or not a string: {}", where, key));
  return *v;
}

double number_of(const toml::table& t, const char* key, const std::string& where) {
  const auto v = toml_number(t.get(key));
  if (!v || !std::isfinite(*v))
    throw std::runtime_error(fmt::format("{}: missing or not a number: {}", where, key));
  return *v;
}

/// A whole number in [lo, hi] (n, sample, dim): anything else would be cast to an integer
/// out of range or truncated without a word.
std::int64_t whole_number_field(const toml::table& t, const char* key, const std::string& where,
                                std::int64_t lo, std::int64_t hi) {
  // A TOML integer is judged as written: rounded to a double, 2^53 + 1 would pass as 2^53.
  const toml::node* node = t.get(key);
  if (const auto* exact = node ? node->as_integer() : nullptr) {
    if (exact->get() >= lo && exact->get() <= hi) return exact->get();
    throw std::runtime_error(fmt::format("{}: {} = {} is not a whole number in [{}, {}]", where,
                                         key, exact->get(), lo, hi));
  }
  const double v = number_of(t, key, where);
  if (const auto whole = whole_number(v, lo, hi)) return *whole;
  throw std::runtime_error(
      fmt::format("{}: {} = {} is not a whole number in [{}, {}]", where, key, v, lo, hi));
}

std::string external_text(const ExternalCampaign& c) {
  toml::array runs, aside;
  for (const auto& r : c.runs)
    runs.push_back(toml::table{{"name", r.name},
                               {"n", r.n},
                               {"phi_init", r.phi_init},
                               {"log10_rate", r.log10_rate},
                               {"sample", r.sample},
                               {"source", r.source},
                               {"source_checksum", r.source_checksum},
                               {"simulator", r.simulator},
                               {"simulator_version", r.simulator_version},
                               {"origin", r.origin}});
  for (const auto& s : c.set_aside)
    aside.push_back(toml::table{{"file", s.file}, {"reason", s.reason}});
  toml::table t{{"name", c.name},
                {"phi_step", c.phi_step},
                {"dim", c.dim},
                {"diameter_ratio", c.diameter_ratio},
                {"contact", c.contact},
                {"dynamics", c.dynamics},
                {"q", c.quality_factor},
                {"run", std::move(runs)},
                {"set_aside", std::move(aside)}};
  std::ostringstream text;
  text << "# An external campaign: runs imported by `jam campaign import` "
          "(docs/cross-simulator.md)\n"
       << toml_text(t) << "\n";
  return text.str();
}

/// Whether `name` is one of jam's temporaries, "<name>.<pid>-<tid>.partial"
/// (AtomicFile::temporary_name): an import's own while it writes, not a run.
bool is_temporary_name(const std::string& name) {
  static const std::regex pattern(R"(.+\.[0-9]+-[0-9]+\.partial)");
  return std::regex_match(name, pattern);
}

}  // namespace

void write_external_campaign(const std::string& directory, const ExternalCampaign& c) {
  const std::string path = (fs::path(directory) / kFile).string(), text = external_text(c);
  std::error_code ec;
  if (fs::symlink_status(path, ec).type() == fs::file_type::regular) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream existing;
    existing << in.rdbuf();
    if (in && existing.str() == text) return;
  }
  write_replacing(path, text);
}

std::vector<std::string> unlisted_run_files(const std::string& directory,
                                            const ExternalCampaign& c) {
  std::set<std::string> listed;
  for (const auto& r : c.runs) listed.insert(r.name + ".h5");
  std::vector<std::string> unlisted;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(directory) / "runs", ec)) {
    const std::string name = e.path().filename().string();
    if (!listed.count(name) && !is_temporary_name(name)) unlisted.push_back(e.path().string());
  }
  std::sort(unlisted.begin(), unlisted.end());
  return unlisted;
}

bool is_plain_campaign_name(const std::string& name) {
  const auto word = [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || std::strchr("._+-", ch) != nullptr;
  };
  return !name.empty() && name.size() <= 255 && std::all_of(name.begin(), name.end(), word) &&
         (std::isalnum(static_cast<unsigned char>(name[0])) || name[0] == '_');
}

bool is_external_campaign(const std::string& directory) {
  return fs::exists(fs::path(directory) / kFile);
}

ExternalCampaign read_external_campaign(const std::string& directory) {
  const std::string path = (fs::path(directory) / kFile).string();
  const toml::table t = read_toml_file("external campaign", path);
  ExternalCampaign c;
  c.name = text_of(t, "name", path);
  c.phi_step = number_of(t, "phi_step", path);
  c.dim = static_cast<int>(whole_number_field(t, "dim", path, 2, 3));
  c.diameter_ratio = number_of(t, "diameter_ratio", path);
  c.contact = text_of(t, "contact", path);
  c.dynamics = text_of(t, "dynamics", path);
  c.quality_factor = number_of(t, "q", path);
  if (!is_plain_campaign_name(c.name))
    throw std::runtime_error(fmt::format(
        "{}: name '{}' is not one plain word (letters, digits and . _ + -)", path, c.name));
  if (!(c.phi_step > 0 && c.phi_step <= 0.05))
    throw std::runtime_error(fmt::format("{}: phi_step {} must be in (0, 0.05]", path, c.phi_step));
  // The model and each run's n by the open run format's own rules (open_run_limits.json).
  OpenRun model;
  model.dim = c.dim;
  model.n = 2;
  model.diameter_ratio = c.diameter_ratio;
  model.contact = c.contact;
  model.dynamics = c.dynamics;
  model.quality_factor = c.quality_factor;
  validate_open_run_model(model, path);
  if (const auto* runs = t["run"].as_array()) {
    for (std::size_t k = 0; k < runs->size(); ++k) {
      const auto* r = (*runs)[k].as_table();
      const std::string where = fmt::format("{}: run[{}]", path, k);
      if (!r) throw std::runtime_error(where + " is not a table");
      ExternalRun x;
      x.name = text_of(*r, "name", where);
      if (x.name.find('/') != std::string::npos || x.name.find("..") != std::string::npos)
        throw std::runtime_error(fmt::format("{}: name '{}' is not a run name", where, x.name));
      x.n = whole_number_field(*r, "n", where, 1, kMaxExactWhole);
      model.n = x.n;
      validate_open_run_model(model, where);
      x.phi_init = number_of(*r, "phi_init", where);
      if (!(x.phi_init > 0 && x.phi_init < 1))
        throw std::runtime_error(
            fmt::format("{}: phi_init {} must be in (0, 1)", where, x.phi_init));
      x.log10_rate = number_of(*r, "log10_rate", where);
      x.sample = whole_number_field(*r, "sample", where, 0, kMaxExactWhole);
      x.source = text_of(*r, "source", where);
      x.source_checksum = text_of(*r, "source_checksum", where);
      x.simulator = text_of(*r, "simulator", where);
      x.simulator_version = text_of(*r, "simulator_version", where);
      x.origin = (*r)["origin"].value_or(std::string());
      c.runs.push_back(std::move(x));
    }
  }
  if (const auto* aside = t["set_aside"].as_array())
    for (const auto& a : *aside)
      if (const auto* s = a.as_table())
        c.set_aside.push_back({text_of(*s, "file", path), text_of(*s, "reason", path)});
  return c;
}

std::string stored_run_problem(const std::string& directory, const ExternalRun& run,
                               OpenRun* read) {
  try {
    const std::string path = (fs::path(directory) / "runs" / (run.name + ".h5")).string();
    OpenRun r = read_open_run(path);
    if (file_checksum(path) != run.source_checksum)
      return "changed since it was imported (its checksum differs)";
    if (read) *read = std::move(r);
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

int print_external_status(const std::string& directory, bool json) {
  const ExternalCampaign c = read_external_campaign(directory);
  std::map<std::tuple<std::int64_t, double, double>, std::pair<int, int>> ensembles;  // ok, bad
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& r : c.runs) {
    const std::string problem = stored_run_problem(directory, r);
    auto& [ok, bad] = ensembles[{r.n, r.phi_init, r.log10_rate}];
    (problem.empty() ? ok : bad) += 1;
    runs.push_back({{"name", r.name},
                    {"status", problem.empty() ? "done" : "corrupt"},
                    {"detail", problem},
                    {"simulator", r.simulator},
                    {"source", r.source}});
    if (!json && !problem.empty())
      fmt::print("corrupt  {}: {}\n", visible(r.name), visible(problem));
  }
  int corrupt = 0;
  for (const auto& [key, counts] : ensembles) corrupt += counts.second;
  const std::vector<std::string> unlisted = unlisted_run_files(directory, c);
  if (json) {
    nlohmann::json aside = nlohmann::json::array();
    for (const auto& s : c.set_aside) aside.push_back({{"file", s.file}, {"reason", s.reason}});
    fmt::print("{}\n", nlohmann::json{{"campaign", c.name},
                                      {"external", true},
                                      {"runs", runs},
                                      {"set_aside", aside},
                                      {"unlisted", unlisted}}
                           .dump(2));
    return corrupt ? 1 : 0;
  }
  fmt::print(
      "{} (external: {} runs imported, {} set aside; model dim {}, diameter ratio {}, {}, "
      "{})\n",
      visible(c.name), c.runs.size(), c.set_aside.size(), c.dim, c.diameter_ratio,
      visible(c.contact), visible(c.dynamics));
  for (const auto& [key, counts] : ensembles)
    fmt::print("  n {:>6}  phi_init {:<6g}  rate 1e{:<6g}  {} runs{}\n", std::get<0>(key),
               std::get<1>(key), std::get<2>(key), counts.first,
               counts.second ? fmt::format(", {} corrupt", counts.second) : "");
  for (const auto& s : c.set_aside)
    fmt::print("set aside  {}: {}\n", visible(s.file), visible(s.reason));
  for (const auto& path : unlisted) fmt::print("unlisted  {}: {}\n", visible(path), kUnlisted);
  return corrupt ? 1 : 0;
}

}  // namespace jam
