#pragma once
// Fitted parameters of two fits judged against a margin (fit_parameters_check.cpp, and the
// compare check's compare_fit and compare_fit_phi_j, compare_check.cpp): each parameter's
// difference is t = |Delta| / sigma, sigma from both jackknife errors, judged with Student's t
// at (samples - 1) degrees of freedom (the jackknife's): detected beyond the (1 - detect / 2)
// quantile, effects beyond |Delta| + t_(1 - pass) sigma excluded (two one-sided tests at
// pass). One verdict may judge several parameters: the largest t and the widest bound decide.
#include <cstdint>
#include <string>
#include <vector>

#include "checks/verdict.hpp"

namespace jam::checks {

struct ParameterDifference {
  const char* name;
  double a, b, delta, sigma;  // delta, sigma in the margin's unit
};

/// Judges one verdict of check `check` on the differences of its parameters; the reason names
/// each parameter's values and difference, and those that differ.
Verdict judge_parameters(const std::string& check, const std::string& case_name,
                         const std::vector<ParameterDifference>& diffs, std::int64_t samples,
                         double detect, double pass, double margin);

}  // namespace jam::checks
