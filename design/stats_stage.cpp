#include "design/stats_stage.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "checks/fit_inputs.hpp"
#include "sim/io/output_path.hpp"
#include "stats/stats_inputs.hpp"

namespace jam::design {

stats::FitVerdicts declared_fit_verdicts(const std::string& directory) {
  try {
    return checks::fit_verdicts(directory);
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "jam stats: {}: the fit uses no verdicts\n", e.what());
    return {};
  }
}

void write_campaign_stats(const std::string& directory, const stats::StatsOptions& o, bool refit) {
  // The output, checked before the work (output_path.hpp).
  const std::string out =
      output_file_target((std::filesystem::path(directory) / "stats.h5").string());
  const auto started = std::chrono::steady_clock::now();
  // What the runs are, taken before they are read: a run finished meanwhile leaves the file
  // out of date, never taken for averaged (stats_inputs.hpp). A refit keeps the earlier file's.
  const std::string inputs = refit ? std::string() : stats::inputs_checksum(directory);
  stats::CampaignStats s = refit ? stats::refit_campaign_stats(directory, o)
                                 : stats::compute_campaign_stats(directory, o);
  if (!refit) s.inputs_checksum = inputs;
  s.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stats::write_stats_file(out, s, o);
  fmt::print("{}", stats::format_stats_summary(s));
  fmt::print("wrote {}\n", out);
}

void average_campaign(const std::string& directory) {
  stats::StatsOptions options;
  options.verdicts = declared_fit_verdicts(directory);
  write_campaign_stats(directory, options);
}

}  // namespace jam::design
