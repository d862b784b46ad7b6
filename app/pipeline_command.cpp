#include "app/pipeline_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/check_options.hpp"
#include "app/report_command.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"
#include "design/pipeline_stages.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam {
namespace fs = std::filesystem;

void add_pipeline_command(CLI::App& app, PipelineArgs& a) {
  CLI::App* p = app.add_subcommand(
      "pipeline",
      "The main job: run a campaign, then redo stats, checks and the report only when their "
      "inputs changed");
  p->add_option("file", a.file, "Campaign file (TOML)")->required();
  p->add_option("--report", a.report, "Report directory (default reports/<campaign name>)");
  p->add_option("--jobs", a.jobs, "Runs at once (default: all cores)");
  // The options of `jam check all`, from the one table (design/judging_options.cpp).
  add_judging_options(p, a.judging);
  p->footer(
      "Exit status: 0 done (the verdicts are in the report's summary), 1 runs failed, "
      "2 a tool error, 130 interrupted.");
}

namespace {

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
  design::average_unless_current(averaged);
  throw_if_stop_requested("checks.json");
  design::judge_unless_up_to_date(dir, a.judging, campaign.compare_with);
  throw_if_stop_requested("the report");
  const design::FileTime report_input =
      std::max(design::modified(dir / "checks.json"), design::modified(dir / "stats.h5"));
  // What jam printed comes before the report's own output (both on standard output).
  std::fflush(stdout);
  if (design::stale(report / "index.html", report_input)) {
    ReportArgs r;
    r.directory = dir.string();
    r.out = report.string();
    // A stop is passed on to the report's Python, which removes its temporary directory.
    const int shown = run_report_command(r);
    throw_if_stop_requested("the report");
    if (shown != 0) return shown;
  } else {
    fmt::print("report: {} is up to date\n", (report / "index.html").string());
  }
  return 0;
}

}  // namespace

int run_pipeline_command(const PipelineArgs& a, const Ranks& ranks) {
  design::validate_judging(a.judging);  // a bad check option: one line, before any run
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
