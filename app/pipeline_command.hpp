#pragma once
// `jam pipeline FILE`: the main job in one command. Runs the campaign (resuming it), then
// redoes the statistics, the checks and the report only when their inputs changed since they
// were last made (a newer run file, campaign file or manifest for stats.h5; a newer stats.h5
// or campaign file, or other check options than checks.json records, for checks.json; newer
// checks or statistics for the report: design/pipeline_stages.hpp).
#include <CLI/CLI.hpp>
#include <string>

#include "campaign/ranks.hpp"
#include "design/judging_options.hpp"

namespace jam {

struct PipelineArgs {
  std::string file;
  std::string report;  // report directory (default reports/<campaign name>)
  int jobs = 0;
  design::JudgingArgs judging;  // the check options, as `jam check` takes them
};

void add_pipeline_command(CLI::App& app, PipelineArgs& args);

/// 1 when runs failed, 0 otherwise (the verdicts are in the report's summary); 2 on errors.
int run_pipeline_command(const PipelineArgs& args, const Ranks& ranks);

}  // namespace jam
