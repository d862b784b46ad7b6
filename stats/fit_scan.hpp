#pragma once
// The scan of scaling fits over phi windows and rate_max (the paper's Fig. 2), and the choice
// of the representative fit: the narrowest window and the slowest rate_max whose fit is of
// quality ok, using only rates that the phi_init check clears (no fit of quality ok: the
// slowest with a result, flagged poor). Whether the other rate_max's fits agree with it (a
// plateau) is said, not required; the scan's systematic error is the largest distance of any
// fit of quality ok from it, so a drift with rate_max widens the error instead of choosing the
// fit. The paper's own protocol (rate_max 10^-6.5, narrowest window) is labelled, not chosen.
#include <string>
#include <vector>

#include "stats/campaign_stats.hpp"

namespace jam::stats {

/// What the phi_init verdicts declared to the fit (fit_verdicts.hpp: those of DIR/checks.json,
/// else of checks-phi_init.json) say about the rates of the fitted ensembles (size n,
/// phi_init).
RateClearance read_clearance(const FitVerdicts& verdicts, std::int64_t n, double fit_phi_init,
                             double lowest_phi_init);

/// Fits every (window, rate_max) of `data` (one ensemble per rate) and picks the representative.
/// `variable` names the averaging ("phi" or "Z") in messages.
FitScan scan_fits(std::vector<FitEnsemble> data, const StatsOptions& options,
                  const RateClearance& clearance, const std::string& variable);

}  // namespace jam::stats
