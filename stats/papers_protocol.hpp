#pragma once
// The paper's own fitting protocol as one labelled fit beside the scan (its Figs. 3-4 and the
// supplement): the sizes pooled "since we find no size dependence", fifth-order ln f, |x| <= 1,
// rate <= 10^-6.5, the narrowest window of the scan. It is a row to compare with, never the
// representative, and nothing in it reads the paper's values. The sizes are pooled only where
// the campaign's finite_size check allows it: its pooled verdicts at constant phi, for the
// fitted phi_init, pass at every fitted rate (DIR/checks.json); otherwise the largest size is
// fitted alone and the words say why.
#include <optional>
#include <string>

#include "stats/campaign_stats.hpp"

namespace jam::stats {

/// The paper's polynomial order of ln f (its Eq. 1 fits).
constexpr int kPapersOrder = 5;

/// Fits s's ensembles of s.fit_phi_init by the paper's protocol; options.verdicts holds the
/// finite_size verdicts declared to the fit, if any (fit_verdicts.hpp). Empty when the
/// campaign has no rate <= 10^-6.5.
std::optional<PapersProtocolFit> fit_papers_protocol(const CampaignStats& s,
                                                     const StatsOptions& options);

}  // namespace jam::stats
