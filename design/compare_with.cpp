#include "design/compare_with.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "checks/stats_data.hpp"

namespace jam::design {
namespace {

/// "PASS", "FAIL" or "INCONCLUSIVE", as the report's headline words them (expected failures
/// apart).
std::string outcome_word(const std::vector<checks::Verdict>& verdicts) {
  const int status = checks::exit_status(verdicts);
  return status == 1 ? "FAIL" : status == 3 ? "INCONCLUSIVE" : "PASS";
}

}  // namespace

std::vector<Comparison> append_comparisons(std::vector<checks::Verdict>& verdicts,
                                           const std::vector<std::string>& compare_with,
                                           const std::string& campaign_name,
                                           const checks::CheckInputs& in) {
  std::vector<Comparison> out;
  for (const std::string& other : compare_with) {
    if (!std::filesystem::is_directory(other))
      throw std::runtime_error(fmt::format("compare_with: {}: no such campaign directory", other));
    checks::CheckInputs compare = in;
    compare.directory = other;
    compare.baseline_directory = in.directory;
    const std::string other_name = checks::read_stats(other).campaign;
    out.push_back({other, verdicts.size(), verdicts.size()});
    for (checks::Verdict v : checks::run_checks("compare", compare)) {
      if (const auto at = v.case_name.find("DIR vs REF"); at != std::string::npos)
        v.case_name.replace(at, 10, fmt::format("{} vs {}", other_name, campaign_name));
      else
        v.case_name = fmt::format("{} vs {}: {}", other_name, campaign_name, v.case_name);
      verdicts.push_back(std::move(v));
    }
    out.back().end = verdicts.size();
  }
  return out;
}

// Another code's verdicts never turn this campaign's headline (a planted wrong code once made
// the reference FAIL); they count in the exit status (checks::exit_status of all).
void print_headlines(const std::vector<checks::Verdict>& verdicts,
                     const std::vector<Comparison>& comparisons) {
  if (comparisons.empty()) return;
  const std::vector<checks::Verdict> own(
      verdicts.begin(), verdicts.begin() + static_cast<std::ptrdiff_t>(comparisons[0].begin));
  fmt::print("this campaign's own checks: {}: {}\n", outcome_word(own),
             checks::outcome_counts(own));
  for (const Comparison& c : comparisons) {
    const std::vector<checks::Verdict> theirs(
        verdicts.begin() + static_cast<std::ptrdiff_t>(c.begin),
        verdicts.begin() + static_cast<std::ptrdiff_t>(c.end));
    fmt::print("compare with {}: {}: {}\n", c.directory, outcome_word(theirs),
               checks::outcome_counts(theirs));
  }
}

}  // namespace jam::design
