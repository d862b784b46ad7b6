#include "app/pipeline_command.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/check_command.hpp"
#include "app/report_command.hpp"
#include "app/stats_command.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"
#include "checks/verdict_file.hpp"
#include "design/stats_stage.hpp"
#include "sim/run/stop_signal.hpp"
#include "stats/fit_verdicts.hpp"
#include "stats/stats_inputs.hpp"

namespace jam {
namespace fs = std::filesystem;
namespace {

using Time = fs::file_time_type;

Time modified(const fs::path& p) {
  std::error_code ec;
  const Time t = fs::last_write_time(p, ec);
  return ec ? Time::min() : t;
}

/// Whether `output` is missing or older than `input`.
bool stale(const fs::path& output, Time input) {
  return !fs::exists(output) || modified(output) < input;
}

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

/// `check all`, when stats.h5 or the campaign file is newer than checks.json or the options
/// differ from those it records (check_record: the options as given and every check's margin
/// as used).
void judge_unless_up_to_date(const fs::path& dir, const JudgingArgs& judging,
                             const std::vector<std::string>& compare_with) {
  CheckArgs check;
  check.name = "all";
  check.directory = dir.string();
  check.judging = judging;
  check.table = false;  // the report's summary prints it, with a headline per check
  const fs::path checks_json = dir / "checks.json";
  Time input = std::max(modified(dir / "stats.h5"), modified(dir / "campaign.toml"));
  for (const auto& other : compare_with)
    input = std::max(input, modified(fs::path(other) / "stats.h5"));
  const bool inputs_newer = stale(checks_json, input);
  if (!inputs_newer && recorded_options(checks_json) == check_record(check)) {
    fmt::print("checks: {} is up to date\n", checks_json.string());
    return;
  }
  if (!inputs_newer)
    fmt::print("checks: {} was judged with other options: judging again\n", checks_json.string());
  run_check_command(check);  // its verdicts are the report's to show, whatever they are
}

}  // namespace

void add_pipeline_command(CLI::App& app, PipelineArgs& a) {
  CLI::App* p = app.add_subcommand(
      "pipeline",
      "The main job: run a campaign, then redo stats, checks and the report only when their "
      "inputs changed");
  p->add_option("file", a.file, "Campaign file (TOML)")->required();
  p->add_option("--report", a.report, "Report directory (default reports/<campaign name>)");
  p->add_option("--jobs", a.jobs, "Runs at once (default: all cores)");
  // The options of `jam check all`, from the one table (check_options.cpp).
  add_judging_options(p, a.judging);
  p->footer(
      "Exit status: 0 done (the verdicts are in the report's summary), 1 runs failed, "
      "2 a tool error, 130 interrupted.");
}

namespace {

/// Throws Interrupted when a stop was asked for: between stages, before the next one begins.
void stage_boundary(const char* next) {
  throw_if_stop_requested(next);
}

/// stats.h5 of each averaged campaign, unless it still describes that campaign's runs
/// (stats_inputs.hpp: the same definition `jam check` refuses by) and its fit the verdicts
/// declared to it.
void average_unless_current(const std::vector<fs::path>& averaged) {
  for (const fs::path& d : averaged) {
    stage_boundary("stats.h5");
    const fs::path stats_file = d / "stats.h5";
    const bool present = fs::exists(fs::symlink_status(stats_file));
    std::string why = present ? stats::stale_stats_reason(d.string()) : std::string();
    if (present && why.empty())
      why = stats::fit_verdicts_change(d.string(), design::declared_fit_verdicts(d.string()));
    if (present && why.empty()) {
      fmt::print("stats: {} is up to date\n", stats_file.string());
      continue;
    }
    if (present)
      fmt::print("stats: {} is out of date ({}): averaging again\n", stats_file.string(), why);
    StatsArgs stats;
    stats.directory = d.string();
    run_stats_command(stats);
  }
}

/// Stats, checks and the report, each only when its inputs changed; a stop asked for ends it
/// at the next stage (Interrupted) or sooner, with nothing of the stage published.
int judge_and_draw(const Campaign& campaign, const PipelineArgs& a) {
  const fs::path dir(campaign.output);
  const fs::path report =
      a.report.empty() ? fs::path("reports") / campaign.name : fs::path(a.report);
  // This campaign's statistics, and those of the campaigns it is compared with (compare_with:
  // other simulators' runs, imported).
  std::vector<fs::path> averaged = {dir};
  for (const auto& other : campaign.compare_with) averaged.emplace_back(other);
  average_unless_current(averaged);
  stage_boundary("checks.json");
  judge_unless_up_to_date(dir, a.judging, campaign.compare_with);
  stage_boundary("the report");
  const Time report_input = std::max(modified(dir / "checks.json"), modified(dir / "stats.h5"));
  // What jam printed comes before the report's own output (both on standard output).
  std::fflush(stdout);
  if (stale(report / "index.html", report_input)) {
    ReportArgs r;
    r.directory = dir.string();
    r.out = report.string();
    // A stop is passed on to the report's Python, which removes its temporary directory.
    const int shown = run_report_command(r);
    stage_boundary("the report");
    if (shown != 0) return shown;
  } else {
    fmt::print("report: {} is up to date\n", (report / "index.html").string());
  }
  return 0;
}

}  // namespace

int run_pipeline_command(const PipelineArgs& a, const Ranks& ranks) {
  validate_judging(a.judging);  // a bad check option: one line, before any run
  const Campaign campaign = read_campaign(a.file);
  // A compare_with campaign that is not there is a mistake in the file: said now, naming it,
  // not after the runs as a campaign file that cannot be read.
  for (const auto& other : campaign.compare_with)
    if (!fs::is_directory(other))
      throw std::runtime_error(fmt::format("compare_with: {}: no such campaign directory", other));
  // The campaign's handlers (stop_signal.hpp), installed before it begins: the first SIGINT or
  // SIGTERM, in any stage, ends the pipeline with 130 (a second one at once).
  install_stop_handlers();
  CampaignRunOptions run;
  run.jobs = a.jobs;
  const int status = run_campaign(campaign, run, ranks);
  if (status != 0 || ranks.rank != 0) return status;
  try {
    return judge_and_draw(campaign, a);
  } catch (const Interrupted& e) {
    std::fflush(stdout);
    fmt::print(stderr, "jam pipeline: {}; run it again to go on\n", e.what());
    return 130;
  }
}

}  // namespace jam
