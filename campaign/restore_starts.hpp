#pragma once
// The starts a campaign reads from another (campaign_file.hpp, chain_starts_from), rewritten
// where they are gone. A campaign keeps a chained start only until its child is done, and a
// snapshot of a finished campaign holds its run files alone; runs redone from its starts (`jam
// campaign converge`) need them again. Each is rewritten by the run of that campaign that left
// it, run again only as far as the start (RunControl::start_only): the same trajectory, so the
// same start bit for bit, for a fraction of the run's cost; parents first, when a parent's own
// start is gone too. Under that campaign's lock.
#include <cstddef>

#include "campaign/campaign_file.hpp"

namespace jam {

/// Rewrites what is missing; returns how many starts were rewritten. Throws CampaignError
/// naming the run when one that must leave a start is not done in that campaign.
std::size_t restore_starts(const Campaign& c, bool quiet);

}  // namespace jam
