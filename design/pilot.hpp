#pragma once
// `jam campaign plan FILE --pilot K`: K samples of every ensemble of the campaign, run and
// judged in <output>-pilot-K (a campaign of its own: the same seeds, so its runs are the
// campaign's first K samples), whose runs' scatter then tells the planner what the full design
// can decide (design/plan_decidability.hpp). Resumes like any campaign.
#include <string>

#include "campaign/campaign_file.hpp"
#include "campaign/campaign_runner.hpp"
#include "campaign/ranks.hpp"

namespace jam {

/// The pilot's campaign: c with K samples, its output <output>-pilot-K.
Campaign pilot_campaign(const Campaign& c, int samples);

/// Runs the pilot, averages it and judges it (checks.json); returns its directory. Throws
/// when a run fails or the stats cannot be made.
std::string run_pilot(const Campaign& pilot, const CampaignRunOptions& run, const Ranks& ranks);

}  // namespace jam
