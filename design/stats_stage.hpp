#pragma once
// The statistics stage as the stages above it run it (`jam stats`, the pilot, the looks of
// --until-decided, `jam pipeline`): the verdicts the fit may use declared (stats/
// fit_verdicts.hpp, read through checks/verdict_file.hpp), DIR/stats.h5 computed, written
// whole and its summary printed. Option parsing stays in app/stats_command.cpp.
#include <string>

#include "stats/campaign_stats.hpp"

namespace jam::design {

/// The verdicts `jam stats DIR` declares to its fit by default (checks::fit_verdicts); none,
/// said on standard error, when a verdict file there cannot be read (a damaged one must not
/// block the averages a new judgement needs).
stats::FitVerdicts declared_fit_verdicts(const std::string& directory);

/// Averages DIR's runs (or, with `refit`, refits DIR/stats.h5's averages) with `options` and
/// writes DIR/stats.h5, checked as an output before the work; prints its summary.
void write_campaign_stats(const std::string& directory, const stats::StatsOptions& options,
                          bool refit = false);

/// `jam stats DIR` with its default options: the verdicts DIR declares to the fit
/// (declared_fit_verdicts), DIR/stats.h5 written (write_campaign_stats).
void average_campaign(const std::string& directory);

}  // namespace jam::design
