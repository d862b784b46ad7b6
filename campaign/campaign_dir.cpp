#include "campaign/campaign_dir.hpp"

#include <fmt/format.h>
#include <time.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

#include "campaign/external_campaign.hpp"
#include "campaign/toml_file.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/version.hpp"

namespace jam {
namespace fs = std::filesystem;

namespace {

std::string record_path(const PlannedRun& run) {
  return fs::path(run.config.out).replace_extension(".record").string();
}

}  // namespace

void write_text_if_changed(const std::string& path, const std::string& text) {
  check_input_file("campaign directory file", path);
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::ostringstream existing;
      existing << in.rdbuf();
      if (existing.str() == text) return;
    }
  }
  AtomicFile out(path);
  std::fputs(text.c_str(), out.stream());
  out.commit();
}

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::kDone:
      return "done";
    case RunStatus::kPartial:
      return "partial";
    case RunStatus::kFailed:
      return "failed";
    case RunStatus::kCorrupt:
      return "corrupt";
    case RunStatus::kMissing:
      return "missing";
  }
  return "?";
}

namespace {
/// Whether `name` is one of jam's own temporaries, "<name>.<pid>-<tid>.partial"
/// (AtomicFile::temporary_name): only those are removed, never a user's "x.partial".
bool is_jam_temporary(const std::string& name) {
  static const std::regex pattern(R"(.+\.[0-9]+-[0-9]+\.partial)");
  return std::regex_match(name, pattern);
}
}  // namespace

void remove_stale_temporaries(const std::string& directory) {
  for (const char* sub : {"", "runs", "starts", "chain"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(directory) / sub, ec)) {
      if (is_jam_temporary(e.path().filename().string()) && e.is_regular_file()) {
        fs::remove(e.path(), ec);
      }
    }
  }
}

Campaign stored_campaign(const std::string& directory) {
  // A directory that is not there is a mistyped path, not a damaged campaign: said so, as
  // `jam check` says it.
  std::error_code ec;
  if (!fs::is_directory(directory, ec))
    throw std::runtime_error(fmt::format("{}: no such campaign directory", directory));
  return read_campaign((fs::path(directory) / "campaign.toml").string());
}

void prepare_campaign_directory(const Campaign& c) {
  const fs::path dir(c.output);
  const fs::path stored = dir / "campaign.toml";
  if (is_external_campaign(dir.string()))
    throw ConfigError(fmt::format(
        "output {}: an external campaign (external.toml): its runs are imported with `jam "
        "campaign import`, not run",
        dir.string()));
  if (fs::exists(stored)) {
    const Campaign old = stored_campaign(dir.string());
    const auto before = identity_keys(old), after = identity_keys(c);
    std::string differences;
    for (std::size_t k = 0; k < before.size(); ++k) {
      if (before[k].second != after[k].second) {
        differences += fmt::format("{}{} {} -> {}", differences.empty() ? "" : ", ",
                                   before[k].first, before[k].second, after[k].second);
      }
    }
    if (!differences.empty()) {
      throw CampaignError(fmt::format(
          "{}: refusing to mix runs: {} was run with a campaign that differs in {} (only sizes, "
          "phi_init, log10_rates, samples and first_sample may change)",
          c.source_path, dir.string(), differences));
    }
  }
  std::error_code ec;
  fs::create_directories(dir / "runs", ec);
  if (!ec) fs::create_directories(dir / "starts", ec);
  if (!ec && !c.chain_phi_init.empty()) fs::create_directories(dir / "chain", ec);
  if (ec) {
    throw CampaignError(fmt::format("{}: output: cannot create '{}': {}", c.source_path,
                                    (dir / "runs").string(), ec.message()));
  }
  write_text_if_changed(stored.string(), c.source_text);
}

RunStatus classify_run_file(const std::string& file,
                            const std::function<std::string()>& identity_problem,
                            std::string* detail) {
  if (fs::exists(file)) {
    // Done only when the file is sound and its own stored parameters are the expected run's,
    // whatever campaign.toml and manifest.toml say (they can be deleted or edited).
    const RunFileCheck check = check_run_file(file);
    std::string problem = check.problem;
    if (problem.empty()) problem = identity_problem();
    if (problem.empty()) {
      if (detail && !check.verified) {
        *detail = "unverified: written before run files checksummed their attributes";
      }
      return RunStatus::kDone;
    }
    if (detail) *detail = problem;
    return RunStatus::kCorrupt;
  }
  if (fs::exists(checkpoint_path(file))) return RunStatus::kPartial;
  const std::string record = fs::path(file).replace_extension(".record").string();
  if (const std::optional<RunRecord> r = read_run_record_at(record); r && r->status == "failed") {
    if (detail) *detail = r->error;
    return RunStatus::kFailed;
  }
  return RunStatus::kMissing;
}

RunStatus run_status(const PlannedRun& run, std::string* detail) {
  const RunStatus s = classify_run_file(
      run.config.out, [&run] { return run_identity_problem(run.config.out, run.config); }, detail);
  // A run started from another campaign's chained start (chain_starts_from) whose campaign
  // is not found from here has no planned start to be judged by: said so, not left as a
  // bare mismatch against an empty identity.
  if (s == RunStatus::kCorrupt && detail && run.config.start_identity.empty() &&
      !run.config.read_start.empty())
    *detail = fmt::format(
        "{}; its start cannot be judged from here: the campaign of {} is not found (a "
        "relative chain_starts_from holds from the directory the campaign runs in)",
        *detail, run.config.read_start);
  return s;
}

void write_run_record(const PlannedRun& run, const RunRecord& r) {
  char host[256] = "";
  gethostname(host, sizeof host - 1);
  toml::table t{{"status", r.status},
                {"wall_seconds", r.wall_seconds},
                {"cpu_seconds", r.cpu_seconds},
                {"steps", r.steps},
                {"particle_steps", r.particle_steps},
                {"version", std::string(kVersion)},
                {"host", std::string(host)}};
  if (!r.error.empty()) t.insert("error", r.error);
  write_text_if_changed(record_path(run), toml_text(t) + "\n");
}

std::optional<RunRecord> read_run_record(const PlannedRun& run) {
  return read_run_record_at(record_path(run));
}

std::optional<RunRecord> read_run_record_at(const std::string& path) {
  if (!fs::exists(path)) return std::nullopt;
  check_input_file("run record", path);  // a FIFO is an error, not an unreadable record
  try {
    const toml::table t = read_toml_file("run record", path);
    RunRecord r;
    r.status = t["status"].value_or(std::string());
    r.wall_seconds = toml_number(t.get("wall_seconds")).value_or(0.0);
    r.cpu_seconds = toml_number(t.get("cpu_seconds")).value_or(0.0);
    r.steps = t["steps"].value_or(std::int64_t{0});
    r.particle_steps = t["particle_steps"].value_or(std::int64_t{0});
    r.error = t["error"].value_or(std::string());
    r.version = t["version"].value_or(std::string());
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<double> recorded_core_seconds(const PlannedRun& run) {
  const std::optional<RunRecord> r = read_run_record(run);
  if (!r) return std::nullopt;
  if (r->cpu_seconds > 0) return r->cpu_seconds;
  return r->wall_seconds;
}

}  // namespace jam
