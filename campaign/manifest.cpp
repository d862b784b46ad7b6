#include "campaign/manifest.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "campaign/added_samples.hpp"
#include "campaign/toml_file.hpp"
#include "sim/io/fnv1a.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/version.hpp"

namespace jam {
namespace fs = std::filesystem;

namespace {

/// The key the manifest records of a run's fingerprint (FNV-1a 64, hex).
std::string fingerprint_key(const std::string& fingerprint) {
  Fnv1a h;
  h.add(fingerprint);
  return h.hex();
}

/// The file's text, "" when there is none.
std::string text_of(const fs::path& path) {
  if (!fs::exists(path)) return "";
  check_input_file("campaign directory file", path.string());
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

void write_manifest(const Campaign& c, const std::vector<PlannedRun>& plan) {
  toml::table runs;
  std::int64_t order = 0;
  for (const auto& run : plan) {
    std::string detail;
    const RunStatus s = run_status(run, &detail);
    toml::table entry{{"status", to_string(s)},
                      {"order", order++},
                      {"n", run.n},
                      {"phi_init", run.phi_init},
                      {"log10_rate", run.log10_rate},
                      {"sample", run.sample},
                      {"fingerprint_key", fingerprint_key(fingerprint(run.config))}};
    // A record's cost and version; what an older record lacks (cpu_seconds before they were
    // measured) is left out rather than written as 0.
    if (const std::optional<RunRecord> r = read_run_record(run)) {
      if (r->wall_seconds > 0) entry.insert("wall_seconds", r->wall_seconds);
      if (r->cpu_seconds > 0) entry.insert("cpu_seconds", r->cpu_seconds);
      if (!r->version.empty()) entry.insert("version", r->version);
    }
    if (!detail.empty()) entry.insert("detail", detail);
    runs.insert(run.name, std::move(entry));
  }
  toml::table manifest{{"campaign_file", c.source_path},
                       {"campaign", c.source_text},
                       {"added_samples", text_of(added_samples_path(c))},
                       {"code_version", std::string(kVersion)},
                       {"runs", std::move(runs)}};
  write_text_if_changed((fs::path(c.output) / "manifest.toml").string(),
                        toml_text(manifest) + "\n");
}

std::optional<std::vector<ManifestRun>> read_current_manifest(const std::string& directory) {
  const fs::path dir(directory);
  if (!fs::exists(dir / "manifest.toml")) return std::nullopt;
  try {
    const toml::table t = read_toml_file("manifest", (dir / "manifest.toml").string());
    const auto campaign = t["campaign"].value<std::string>();
    const auto added = t["added_samples"].value<std::string>();
    if (!campaign || !added || *campaign != text_of(dir / "campaign.toml") ||
        *added != text_of(dir / "added-samples.toml"))
      return std::nullopt;
    const toml::table* runs = t["runs"].as_table();
    if (!runs) return std::nullopt;
    std::vector<std::pair<std::int64_t, ManifestRun>> ordered;
    for (const auto& [name, node] : *runs) {
      const toml::table* e = node.as_table();
      if (!e) return std::nullopt;
      const auto order = (*e)["order"].value<std::int64_t>();
      const auto n = (*e)["n"].value<std::int64_t>();
      const auto phi = toml_number(e->get("phi_init"));
      const auto rate = toml_number(e->get("log10_rate"));
      const auto sample = (*e)["sample"].value<std::int64_t>();
      const auto print = (*e)["fingerprint_key"].value<std::string>();
      if (!order || !n || !phi || !rate || !sample || !print) return std::nullopt;
      ordered.push_back({*order, {std::string(name.str()), *n, *phi, *rate, *sample, *print}});
    }
    std::sort(ordered.begin(), ordered.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<ManifestRun> out;
    for (auto& [order, run] : ordered) out.push_back(std::move(run));
    return out;
  } catch (const std::exception&) {
    return std::nullopt;  // a manifest that cannot be read is planned around, as none
  }
}

std::optional<RunStatus> manifest_run_status(const std::string& directory, const ManifestRun& run,
                                             std::string* detail) {
  const std::string file = (fs::path(directory) / "runs" / (run.name + ".h5")).string();
  struct NeedsPlan {};
  try {
    return classify_run_file(
        file,
        [&] {
          const std::optional<std::string> stored = stored_fingerprint(file);
          if (!stored || fingerprint_key(*stored) != run.fingerprint_key) throw NeedsPlan{};
          return std::string();
        },
        detail);
  } catch (const NeedsPlan&) {
    return std::nullopt;
  }
}

}  // namespace jam
