#include "campaign/external_campaign.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "campaign/run_plan.hpp"
#include "campaign/toml_file.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/whole_number.hpp"

namespace fs = std::filesystem;

namespace jam {
namespace {

constexpr const char* kFile = "external.toml";

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
std::int64_t whole_of(const toml::table& t, const char* key, const std::string& where,
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

void write_external(const std::string& directory, const ExternalCampaign& c) {
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
                {"q", c.q},
                {"run", std::move(runs)},
                {"set_aside", std::move(aside)}};
  std::ostringstream text;
  text << "# An external campaign: runs imported by `jam campaign import` "
          "(docs/cross-simulator.md)\n"
       << toml_text(t) << "\n";
  AtomicFile out((fs::path(directory) / kFile).string());
  const std::string s = text.str();
  if (std::fwrite(s.data(), 1, s.size(), out.stream()) != s.size())
    throw WriteError(fmt::format("{}: cannot write {}", directory, kFile));
  out.commit();
}

/// Why r cannot join campaign c ("" when it can); takes c's model from r when c has none yet.
std::string model_mismatch(ExternalCampaign& c, const OpenRun& r) {
  if (c.dim == 0) {
    c.dim = r.dim, c.diameter_ratio = r.diameter_ratio, c.contact = r.contact;
    c.dynamics = r.dynamics, c.q = r.q;
    return "";
  }
  if (r.dim != c.dim) return fmt::format("dim {}, the campaign's {}", r.dim, c.dim);
  if (std::abs(r.diameter_ratio - c.diameter_ratio) > 1e-12)
    return fmt::format("diameter_ratio {}, the campaign's {}", r.diameter_ratio, c.diameter_ratio);
  if (r.contact != c.contact) return fmt::format("contact {}, the campaign's {}", r.contact, c.contact);
  if (r.dynamics != c.dynamics || std::abs(r.q - c.q) > 1e-12)
    return fmt::format("dynamics {} (Q {}), the campaign's {} (Q {})", r.dynamics, r.q, c.dynamics,
                       c.q);
  return "";
}

/// The campaign directory to import into, made ready: an external campaign, or new.
ExternalCampaign open_for_import(const fs::path& d, const ImportOptions& o) {
  check_output_directory("directory", d.string());
  if (o.phi_step && !(*o.phi_step > 0 && *o.phi_step <= 0.05))
    throw std::runtime_error(fmt::format("--phi-step {}: must be in (0, 0.05]", *o.phi_step));
  if (is_external_campaign(d.string())) {
    ExternalCampaign c = read_external_campaign(d.string());
    if (o.phi_step && std::abs(*o.phi_step - c.phi_step) > 1e-15)
      throw std::runtime_error(fmt::format("--phi-step {}: the campaign's is {}", *o.phi_step,
                                           c.phi_step));
    return c;
  }
  if (fs::exists(d / "campaign.toml") || fs::exists(d / "manifest.toml"))
    throw std::runtime_error(fmt::format(
        "{}: a planned campaign (campaign.toml); import into a directory of its own", d.string()));
  if (fs::exists(d) && !fs::is_empty(d))
    throw std::runtime_error(fmt::format(
        "{}: not empty and not an external campaign; import into a new directory", d.string()));
  ExternalCampaign c;
  c.name = o.name.empty() ? fs::absolute(d).lexically_normal().filename().string() : o.name;
  if (c.name.empty()) c.name = "external";
  c.phi_step = o.phi_step.value_or(0.0005);
  fs::create_directories(d / "runs");
  return c;
}

}  // namespace

bool is_external_campaign(const std::string& directory) {
  return fs::exists(fs::path(directory) / kFile);
}

ExternalCampaign read_external_campaign(const std::string& directory) {
  const std::string path = (fs::path(directory) / kFile).string();
  const toml::table t = read_toml_file("external campaign", path);
  ExternalCampaign c;
  c.name = text_of(t, "name", path);
  c.phi_step = number_of(t, "phi_step", path);
  c.dim = static_cast<int>(whole_of(t, "dim", path, 2, 3));
  c.diameter_ratio = number_of(t, "diameter_ratio", path);
  c.contact = text_of(t, "contact", path);
  c.dynamics = text_of(t, "dynamics", path);
  c.q = number_of(t, "q", path);
  if (!(c.phi_step > 0 && c.phi_step <= 0.05))
    throw std::runtime_error(fmt::format("{}: phi_step {} must be in (0, 0.05]", path, c.phi_step));
  if (const auto* runs = t["run"].as_array()) {
    for (std::size_t k = 0; k < runs->size(); ++k) {
      const auto* r = (*runs)[k].as_table();
      const std::string where = fmt::format("{}: run[{}]", path, k);
      if (!r) throw std::runtime_error(where + " is not a table");
      ExternalRun x;
      x.name = text_of(*r, "name", where);
      if (x.name.find('/') != std::string::npos || x.name.find("..") != std::string::npos)
        throw std::runtime_error(fmt::format("{}: name '{}' is not a run name", where, x.name));
      x.n = whole_of(*r, "n", where, 1, kMaxExactWhole);
      x.phi_init = number_of(*r, "phi_init", where);
      x.log10_rate = number_of(*r, "log10_rate", where);
      x.sample = whole_of(*r, "sample", where, 0, kMaxExactWhole);
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

ImportOutcome import_runs(const std::string& directory, const std::vector<std::string>& files,
                          const ImportOptions& options) {
  const fs::path d(directory);
  ExternalCampaign c = open_for_import(d, options);
  ImportOutcome out;
  auto aside = [&](const std::string& file, const std::string& reason) {
    out.set_aside.push_back({file, reason});
    c.set_aside.push_back({file, reason});
  };
  for (const std::string& file : files) {
    OpenRun r;
    std::string checksum;
    try {
      r = read_open_run(file);
      checksum = file_checksum(file);
    } catch (const std::exception& e) {
      aside(file, e.what());
      continue;
    }
    if (const std::string why = model_mismatch(c, r); !why.empty()) {
      aside(file, why);
      continue;
    }
    ExternalRun x{"", r.n, r.sample, r.phi_init, std::log10(r.compression_rate),
                  fs::absolute(file).lexically_normal().string(), checksum, r.simulator,
                  r.simulator_version, r.source};
    // Its ensemble: the first run's nominal phi_init and rate, within what a run name tells.
    for (const auto& e : c.runs)
      if (e.n == x.n && std::abs(e.phi_init - x.phi_init) <= 1e-6 &&
          std::abs(e.log10_rate - x.log10_rate) <= 1e-9) {
        x.phi_init = e.phi_init, x.log10_rate = e.log10_rate;
        break;
      }
    x.name = run_name(x.n, x.phi_init, x.log10_rate, x.sample);
    const auto same = std::find_if(c.runs.begin(), c.runs.end(),
                                   [&](const ExternalRun& e) { return e.name == x.name; });
    if (same != c.runs.end()) {
      if (same->source_checksum == checksum) {
        ++out.already;
      } else {
        aside(file, fmt::format("sample {} of n {}, phi_init {:g}, rate 1e{:g} is already "
                                "imported (from {}); give it another sample id",
                                x.sample, x.n, x.phi_init, x.log10_rate, same->source));
      }
      continue;
    }
    copy_file_atomically(file, (d / "runs" / (x.name + ".h5")).string());
    c.runs.push_back(std::move(x));
    ++out.imported;
  }
  write_external(directory, c);
  return out;
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
    if (!json && !problem.empty()) fmt::print("corrupt  {}: {}\n", r.name, problem);
  }
  int corrupt = 0;
  for (const auto& [key, counts] : ensembles) corrupt += counts.second;
  if (json) {
    nlohmann::json aside = nlohmann::json::array();
    for (const auto& s : c.set_aside) aside.push_back({{"file", s.file}, {"reason", s.reason}});
    fmt::print("{}\n", nlohmann::json{{"campaign", c.name},
                                      {"external", true},
                                      {"runs", runs},
                                      {"set_aside", aside}}
                           .dump(2));
    return corrupt ? 1 : 0;
  }
  fmt::print("{} (external: {} runs imported, {} set aside; model dim {}, diameter ratio {}, {}, "
             "{})\n",
             c.name, c.runs.size(), c.set_aside.size(), c.dim, c.diameter_ratio, c.contact,
             c.dynamics);
  for (const auto& [key, counts] : ensembles)
    fmt::print("  n {:>6}  phi_init {:<6g}  rate 1e{:<6g}  {} runs{}\n", std::get<0>(key),
               std::get<1>(key), std::get<2>(key), counts.first,
               counts.second ? fmt::format(", {} corrupt", counts.second) : "");
  for (const auto& s : c.set_aside) fmt::print("set aside  {}: {}\n", s.file, s.reason);
  return corrupt ? 1 : 0;
}

}  // namespace jam
