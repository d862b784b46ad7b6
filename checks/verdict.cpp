#include "checks/verdict.hpp"

#include <fmt/format.h>

namespace jam::checks {

int exit_status(const std::vector<Verdict>& v) {
  bool inconclusive = false;
  for (const auto& x : v) {
    if (x.status == "fail" && !x.expected_failure) return 1;
    inconclusive = inconclusive || x.status == "inconclusive";
  }
  return inconclusive ? 3 : 0;
}

std::string outcome_counts(const std::vector<Verdict>& v) {
  int pass = 0, fail = 0, inconclusive = 0, expected = 0, expected_passed = 0;
  for (const auto& x : v) {
    if (x.status == "fail") (x.expected_failure ? expected : fail)++;
    if (x.status == "pass") ++pass;
    if (x.status == "pass" && x.expected_failure) ++expected_passed;
    if (x.status == "inconclusive") ++inconclusive;
  }
  std::string out = fmt::format("{} passed, {} failed, {} inconclusive", pass, fail, inconclusive);
  if (expected > 0) out += fmt::format(", {} failed as expected", expected);
  if (expected_passed > 0) out += fmt::format(" ({} expected to fail passed)", expected_passed);
  return out;
}

}  // namespace jam::checks
