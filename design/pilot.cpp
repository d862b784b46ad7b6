#include "design/pilot.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <sstream>
#include <stdexcept>

#include "campaign/toml_file.hpp"
#include "checks/checks.hpp"
#include "checks/verdict_file.hpp"
#include "design/stats_stage.hpp"

namespace jam {

Campaign pilot_campaign(const Campaign& c, int samples) {
  if (samples < 2)
    throw std::invalid_argument(
        fmt::format("--pilot {}: at least 2 samples per ensemble", samples));
  // The campaign's own text with samples, output and name changed: it is what the pilot's
  // directory stores (campaign.toml) and what its stats and checks read back.
  toml::table t = toml::parse(c.source_text);
  t.insert_or_assign("samples", samples);
  t.insert_or_assign("output", fmt::format("{}-pilot-{}", c.output, samples));
  t.insert_or_assign("name", fmt::format("{}-pilot-{}", c.name, samples));
  std::ostringstream text;
  // The name, not the file's path: the text must stay plain ASCII, a path need not be.
  text << "# The pilot of campaign " << c.name << " (jam campaign plan --pilot " << samples << ")\n"
       << toml_text(t) << "\n";
  return parse_campaign(text.str(), c.source_path);
}

std::string run_pilot(const Campaign& pilot, const CampaignRunOptions& run, const Ranks& ranks) {
  if (const int status = run_campaign(pilot, run, ranks); status != 0)
    throw std::runtime_error(
        fmt::format("pilot {}: jam campaign run exited {}", pilot.output, status));
  if (ranks.rank != 0) return pilot.output;
  design::average_campaign(pilot.output);  // as `jam stats DIR`
  checks::CheckOptions options;
  options.margins = pilot.margins;
  const auto verdicts = checks::run_check("all", checks::read_stats(pilot.output), options);
  checks::write_verdict_files(pilot.output, "all", verdicts, pilot.name, 0.0);
  return pilot.output;
}

}  // namespace jam
