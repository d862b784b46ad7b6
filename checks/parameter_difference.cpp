#include "checks/parameter_difference.hpp"

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>

#include "checks/margin.hpp"

namespace jam::checks {

Verdict judge_parameters(const std::string& check, const std::string& case_name,
                         const std::vector<ParameterDifference>& diffs, std::int64_t samples,
                         double detect, double pass, double margin) {
  Verdict v;
  v.check = check;
  v.case_name = case_name;
  v.statistic_name = "max |Delta| / sigma (Student t)";
  const double dof = static_cast<double>(std::max<std::int64_t>(samples - 1, 1));
  const double t_detect = gsl_cdf_tdist_Qinv(detect / 2, dof),
               t_pass = gsl_cdf_tdist_Qinv(pass, dof);
  double statistic = 0, bound = 0, surely = 0, detectable = 0;
  bool detected = false;
  std::string words, differ;
  for (const auto& d : diffs) {
    const double t = d.sigma > 0 ? std::abs(d.delta) / d.sigma : HUGE_VAL;
    statistic = std::max(statistic, t);
    bound = std::max(bound, std::abs(d.delta) + t_pass * d.sigma);
    surely = std::max(surely, std::abs(d.delta) - t_detect * d.sigma);
    detectable = std::max(detectable, t_detect * d.sigma);
    const bool beyond = t > t_detect;
    detected = detected || beyond;
    if (beyond) differ += (differ.empty() ? "" : ", ") + std::string(d.name);
    words += fmt::format("{}{} {:.4g} vs {:.4g}: Delta {} +- {}", words.empty() ? "" : "; ", d.name,
                         d.a, d.b, effect_text(v, d.delta, true), effect_text(v, d.sigma));
  }
  v.statistic = statistic;
  v.threshold = t_detect;
  v.detectable = detectable;
  decide(v, detected, bound, surely, margin);
  v.reason += fmt::format(" ({}; t at {:.0f} degrees of freedom, alpha {:.3g}{})", words, dof,
                          detect, differ.empty() ? "" : "; differ: " + differ);
  return v;
}

}  // namespace jam::checks
