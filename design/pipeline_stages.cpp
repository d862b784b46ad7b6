#include "design/pipeline_stages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "checks/verdict_file.hpp"
#include "design/check_stage.hpp"
#include "design/stats_stage.hpp"
#include "sim/run/stop_signal.hpp"
#include "stats/fit_verdicts.hpp"
#include "stats/stats_inputs.hpp"

namespace jam::design {
namespace fs = std::filesystem;
namespace {

/// The options checks.json says its verdicts were judged with; null when it records none (or
/// cannot be read: then it is judged again, and rewritten; a FIFO there is refused by the
/// check, never waited on here).
nlohmann::json recorded_options(const fs::path& checks_json) {
  if (!fs::is_regular_file(checks_json)) return nullptr;
  try {
    return checks::read_verdict_file(checks_json.string()).options;
  } catch (const std::runtime_error&) {
    return nullptr;
  }
}

}  // namespace

FileTime modified(const fs::path& p) {
  std::error_code ec;
  const FileTime t = fs::last_write_time(p, ec);
  return ec ? FileTime::min() : t;
}

bool stale(const fs::path& output, FileTime input) {
  return !fs::exists(output) || modified(output) < input;
}

void average_unless_current(const std::vector<fs::path>& averaged) {
  for (const fs::path& d : averaged) {
    throw_if_stop_requested("stats.h5");  // between stages, before the next one begins
    const fs::path stats_file = d / "stats.h5";
    const bool present = fs::exists(fs::symlink_status(stats_file));
    std::string why = present ? stats::stale_stats_reason(d.string()) : std::string();
    if (present && why.empty())
      why = stats::fit_verdicts_change(d.string(), declared_fit_verdicts(d.string()));
    if (present && why.empty()) {
      fmt::print("stats: {} is up to date\n", stats_file.string());
      continue;
    }
    if (present)
      fmt::print("stats: {} is out of date ({}): averaging again\n", stats_file.string(), why);
    average_campaign(d.string());  // as `jam stats DIR`
  }
}

void judge_unless_up_to_date(const fs::path& dir, const JudgingArgs& judging,
                             const std::vector<std::string>& compare_with) {
  CheckRequest check;
  check.name = "all";
  check.directory = dir.string();
  check.judging = judging;
  check.table = false;  // the report's summary prints it, with a headline per check
  const fs::path checks_json = dir / "checks.json";
  FileTime input = std::max(modified(dir / "stats.h5"), modified(dir / "campaign.toml"));
  for (const auto& other : compare_with)
    input = std::max(input, modified(fs::path(other) / "stats.h5"));
  const bool inputs_newer = stale(checks_json, input);
  if (!inputs_newer && recorded_options(checks_json) == check_record(check)) {
    fmt::print("checks: {} is up to date\n", checks_json.string());
    return;
  }
  if (!inputs_newer)
    fmt::print("checks: {} was judged with other options: judging again\n", checks_json.string());
  run_check_stage(check);  // its verdicts are the report's to show, whatever they are
}

}  // namespace jam::design
