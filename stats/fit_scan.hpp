#pragma once
// The scan of scaling fits over phi windows and rate_max (the paper's Fig. 2), and the choice
// of the representative fit as the paper makes it: the narrowest window, and the largest
// rate_max (most rates, most decades) from which phi_J, q and 1/(z nu) agree within 2 sigma
// with the fit at every slower rate_max (at least one), using only rates that the phi_init
// check clears; without such a plateau the slowest rate_max's fit, flagged poor.
#include <string>
#include <vector>

#include "stats/campaign_stats.hpp"

namespace jam::stats {

/// What the phi_init verdicts in DIR (checks.json, else checks-phi_init.json) say about the
/// rates of the ensembles (size n, phi_init) that are fitted.
RateClearance read_clearance(const std::string& directory, std::int64_t n, double fit_phi_init,
                             double lowest_phi_init);

/// Fits every (window, rate_max) of `data` (one ensemble per rate) and picks the representative.
/// `variable` names the averaging ("phi" or "Z") in messages.
FitScan scan_fits(std::vector<FitEnsemble> data, const StatsOptions& options,
                  const RateClearance& clearance, const std::string& variable);

}  // namespace jam::stats
