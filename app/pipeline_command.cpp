#include "app/pipeline_command.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "app/check_command.hpp"
#include "app/report_command.hpp"
#include "app/stats_command.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"

namespace jam {
namespace fs = std::filesystem;
namespace {

using Time = fs::file_time_type;

Time modified(const fs::path& p) {
  std::error_code ec;
  const Time t = fs::last_write_time(p, ec);
  return ec ? Time::min() : t;
}

/// The newest of the campaign's run files, its campaign file and manifest.
Time newest_input(const fs::path& dir) {
  Time t = std::max(modified(dir / "campaign.toml"), modified(dir / "manifest.toml"));
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "runs", ec)) {
    if (e.path().extension() == ".h5") t = std::max(t, modified(e.path()));
  }
  return t;
}

/// Whether `output` is missing or older than `input`.
bool stale(const fs::path& output, Time input) {
  return !fs::exists(output) || modified(output) < input;
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
  p->footer(
      "Exit status: 0 done (the verdicts are in the report's summary), 1 runs failed, "
      "2 a tool error, 130 interrupted.");
}

int run_pipeline_command(const PipelineArgs& a, const Ranks& ranks) {
  const Campaign campaign = read_campaign(a.file);
  CampaignRunOptions run;
  run.jobs = a.jobs;
  const int status = run_campaign(campaign, run, ranks);
  if (status != 0 || ranks.rank != 0) return status;

  const fs::path dir(campaign.output);
  const fs::path report =
      a.report.empty() ? fs::path("reports") / campaign.name : fs::path(a.report);
  if (stale(dir / "stats.h5", newest_input(dir))) {
    StatsArgs stats;
    stats.directory = dir.string();
    run_stats_command(stats);
  } else {
    fmt::print("stats: {} is up to date\n", (dir / "stats.h5").string());
  }
  const Time checks_input = std::max(modified(dir / "stats.h5"), modified(dir / "campaign.toml"));
  if (stale(dir / "checks.json", checks_input)) {
    CheckArgs check;
    check.name = "all";
    check.directory = dir.string();
    check.table = false;       // the report's summary prints it, with a headline per check
    run_check_command(check);  // its verdicts are the report's to show, whatever they are
  } else {
    fmt::print("checks: {} is up to date\n", (dir / "checks.json").string());
  }
  const Time report_input = std::max(modified(dir / "checks.json"), modified(dir / "stats.h5"));
  if (stale(report / "index.html", report_input)) {
    ReportArgs r;
    r.directory = dir.string();
    r.out = report.string();
    if (const int shown = run_report_command(r); shown != 0) return shown;
  } else {
    fmt::print("report: {} is up to date\n", (report / "index.html").string());
  }
  return 0;
}

}  // namespace jam
