#pragma once
// Numerical convergence as a verdict (checks/convergence_check.cpp) needs the campaign's runs
// redone at a stricter integrator setting from the same starts. This writes that campaign: part
// of `c` (by default every size, the two slowest rates, the first three samples), the
// compression tolerance a tenth of the campaign's strictest among the rates redone (its
// "auto" resolved per rate, auto_tolerance), the error measured in the largest component
// (error_norm "max": an rms norm lets a localized error grow as sqrt(N) before a step is
// refused), and chained rates started from the campaign's own chained starts
// (chain_starts_from: the stored parents, rewritten where gone). Unchained rates start from
// the same random configuration (the same seed) and relax it themselves. The text is the
// campaign's own with those keys changed, so that `jam campaign run`, `jam stats` and `jam
// check convergence DIR --against OUTPUT` read it as any campaign.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "campaign/campaign_file.hpp"

namespace jam {

struct ConvergenceChoice {
  std::vector<std::int64_t> sizes;  // empty: every size
  std::vector<double> log10_rates;  // empty: the two slowest
  std::int64_t samples = 3;         // the campaign's first samples
  double tolerance_factor = 0.1;
  std::optional<double> phi_stop;  // default: the campaign's
  std::string output;              // default: <output>-convergence
};

/// The campaign file's text. Throws CampaignError naming the choice that `c` cannot meet (a
/// size or rate it does not have, more samples than it holds, a factor outside (0, 1)).
std::string convergence_campaign_text(const Campaign& c, const ConvergenceChoice& choice);

/// `jam campaign converge`: writes `text` (convergence_campaign_text of `c`) to `out`, whole,
/// under a temporary name, and returns what to say: the file, its runs, and the commands that
/// judge it. The caller refuses an `out` that exists.
std::string write_convergence_campaign(const Campaign& c, const std::string& text,
                                       const std::string& out);

}  // namespace jam
