#pragma once
// `jam check all` of a campaign whose file names `compare_with` (other simulators' campaigns,
// imported): each of those campaigns judged against this one, as `jam check compare OTHER
// --against THIS` would, its verdicts named by both campaigns, and the headlines that keep
// another code's verdicts from turning this campaign's own.
#include <cstddef>
#include <string>
#include <vector>

#include "checks/run_checks.hpp"

namespace jam::design {

/// The verdicts of one campaign of compare_with: verdicts[begin, end).
struct Comparison {
  std::string directory;
  std::size_t begin = 0, end = 0;
};

/// Appends the compare verdicts of each campaign of `compare_with` against `in.directory`
/// (the campaign named `campaign_name`), "OTHER vs THIS" in their case names. Throws naming a
/// campaign directory that is not there.
std::vector<Comparison> append_comparisons(std::vector<checks::Verdict>& verdicts,
                                           const std::vector<std::string>& compare_with,
                                           const std::string& campaign_name,
                                           const checks::CheckInputs& in);

/// With comparisons: the headline of this campaign's own checks, then one line per compared
/// campaign; nothing without.
void print_headlines(const std::vector<checks::Verdict>& verdicts,
                     const std::vector<Comparison>& comparisons);

}  // namespace jam::design
