#include "campaign/added_samples.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "campaign/toml_file.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/whole_number.hpp"

namespace jam {
namespace fs = std::filesystem;

namespace {

double number(const toml::table& t, const char* key, const std::string& path) {
  if (const auto v = toml_number(t.get(key))) return *v;
  throw CampaignError(fmt::format("{}: ensemble needs a number '{}'", path, key));
}

}  // namespace

std::optional<EnsembleId> campaign_ensemble(const Campaign& c, const EnsembleId& e) {
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-9; };
  for (auto n : c.sizes)
    for (double phi : c.phi_init)
      for (double r : c.log10_rates)
        if (n == e.n && near(phi, e.phi_init) && near(r, e.log10_rate))
          return EnsembleId{n, phi, r};
  return std::nullopt;
}

std::string added_samples_path(const Campaign& c) {
  return (fs::path(c.output) / "added-samples.toml").string();
}

SampleCounts read_added_samples(const Campaign& c) {
  const std::string path = added_samples_path(c);
  SampleCounts counts;
  if (!fs::exists(fs::symlink_status(path))) return counts;
  toml::table t;
  try {
    t = read_toml_file("added samples", path);
  } catch (const std::runtime_error& e) {
    throw CampaignError(e.what());
  }
  const toml::array* list = t["ensemble"].as_array();
  if (!list) return counts;
  for (const auto& node : *list) {
    const toml::table* e = node.as_table();
    if (!e) throw CampaignError(fmt::format("{}: 'ensemble' entries must be tables", path));
    const double n = number(*e, "n", path), samples = number(*e, "samples", path);
    const auto whole_n = whole_number(n, 0, kMaxExactWhole);
    const auto whole_samples = whole_number(samples, 0, 999'999'999);
    if (!whole_n || !whole_samples) {
      throw CampaignError(
          fmt::format("{}: ensemble n = {}, samples = {}: whole numbers (samples below 1e9)", path,
                      n, samples));
    }
    const EnsembleId given{*whole_n, number(*e, "phi_init", path), number(*e, "log10_rate", path)};
    const std::optional<EnsembleId> found = campaign_ensemble(c, given);
    if (!found) {
      throw CampaignError(fmt::format(
          "{}: ensemble n = {}, phi_init = {}, log10_rate = {} is not one of the campaign's", path,
          given.n, given.phi_init, given.log10_rate));
    }
    const EnsembleId id = *found;
    // An entry at or below the campaign's `samples` is superseded: the campaign file was raised
    // past what the sequence added (every run it names is kept and counted either way).
    if (*whole_samples <= c.samples) continue;
    counts[id] = *whole_samples;
  }
  double runs = 0;
  for (const auto& [id, s] : samples_per_ensemble(c, counts)) runs += static_cast<double>(s);
  if (runs > static_cast<double>(kMaxCampaignRuns)) {
    throw CampaignError(fmt::format("{}: {} runs with the added samples, more than {}", path, runs,
                                    kMaxCampaignRuns));
  }
  return counts;
}

void write_added_samples(const Campaign& c, const SampleCounts& counts) {
  const std::string path = added_samples_path(c);
  if (counts.empty()) {
    std::error_code ec;
    fs::remove(path, ec);
    return;
  }
  toml::array list;
  for (const auto& [id, samples] : counts) {
    list.push_back(toml::table{{"n", id.n},
                               {"phi_init", id.phi_init},
                               {"log10_rate", id.log10_rate},
                               {"samples", samples}});
  }
  std::ostringstream text;
  text << "# Samples added by `jam campaign run --until-decided` (jam writes this file).\n"
       << toml_text(toml::table{{"ensemble", std::move(list)}}) << "\n";
  AtomicFile out(path);
  std::fputs(text.str().c_str(), out.stream());
  out.commit();
}

SampleCounts samples_per_ensemble(const Campaign& c, const SampleCounts& added) {
  SampleCounts all;
  for (auto n : c.sizes)
    for (double phi : c.phi_init)
      for (double lr : c.log10_rates) {
        const auto it = added.find({n, phi, lr});
        all[{n, phi, lr}] = std::max(c.samples, it == added.end() ? 0 : it->second);
      }
  if (c.chain_phi_init.empty()) return all;
  // Slowest to fastest: a chained rate's samples need the same samples of the faster rate.
  const std::vector<std::size_t> order = rates_fastest_first(c);
  for (auto n : c.sizes)
    for (double phi : c.phi_init)
      for (std::size_t i = order.size(); i-- > 1;) {
        if (c.chain_phi_init[order[i]] == 0.0) continue;
        auto& faster = all[{n, phi, c.log10_rates[order[i - 1]]}];
        faster = std::max(faster, all[{n, phi, c.log10_rates[order[i]]}]);
      }
  return all;
}

}  // namespace jam
