#pragma once
// How many samples a pooled verdict needs, estimated from a variance model rather than from
// one verdict's own band.
//
// The pooled statistic (checks/pooled_verdict.hpp) is, to first order, a difference of run
// means: with pbar_k the mean pressure of both sets at point k of the window and w_k the
// verdict's weights, each run i carries one number, its window mean u_i = sum_k w_k p_ik /
// pbar_k, and D ~ mean(u_A) - mean(u_B). So
//   sigma_D^2 = s_A^2 / n_A + s_B^2 / n_B,   s = the runs' scatter of u (the window scatter),
// one number per ensemble, which shrinks as 1/sqrt(n) and sets how many samples a verdict
// needs. One verdict's s, from 10 runs, is uncertain by about a quarter; the s of
// neighbouring rates of the same series (same sizes and starts) lie on a smooth curve, so the
// estimate pools them: ln s^2 fitted linear in log10 rate over the rates within one decade,
// each weighted by its degrees of freedom (pool_window_scatter). Measured on resamples of the
// stored results: docs/statistics-and-checks.md#samples-needed.
#include <cstdint>
#include <string>
#include <vector>

#include "checks/relative_difference.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

/// The window scatter of each set: the sample standard deviation over its runs of u_i at the
/// verdict's points (indices into the rows of `al`) and weights (summing to 1).
struct WindowScatter {
  double a = NAN, b = NAN;
};
WindowScatter window_scatter(const Aligned& al, const std::vector<std::size_t>& points,
                             const std::vector<double>& weight);

/// The samples that would decide a verdict with observed difference D at margin M, when each
/// set's window scatter is s_a, s_b and one sample costs c_a, c_b (core time, relative): the
/// samples at which, were delta the truth, it decides with probability kEstimatePower,
///   pass at   (z_pass + z_power) sigma_D <= M - |delta|   (when |delta| < M),
///   fail at   (z_det + z_power) sigma_D <= |delta| - M   (shown beyond the margin),
/// whichever comes first, taken at the median over delta ~ N(D, sigma_D at the present
/// samples) (the observed D near the margin would make it jump); z are the normal quantiles of
/// levels.pass and levels.detect (both one-sided) and the power. `equal`: the same samples in
/// both sets; `a`, `b`: the cheapest split reaching the same sigma_D (n proportional to s /
/// sqrt(c)), never fewer than the samples present, and more than present in at least one set (the
/// data at hand did not decide), and enough for the permutation test to reach the route's level.
/// NaN when there is no estimate (s not finite).
constexpr double kEstimatePower = 0.8;
struct SamplesNeeded {
  double equal = NAN, a = NAN, b = NAN;
};
SamplesNeeded samples_needed(double difference, double s_a, double s_b, double cost_a,
                             double cost_b, double present_a, double present_b, Levels levels,
                             double margin);

/// The same for a given sigma_D: equal = (s_a^2 + s_b^2) / sigma^2, and the cheapest split.
SamplesNeeded samples_for_sigma(double sigma, double s_a, double s_b, double cost_a, double cost_b,
                                double present_a, double present_b);

/// The estimate in words, for a verdict's reason ("; about 24 samples per set would decide
/// it (...)"), naming the two sets (e.g. "N = 256", "phi_init 0.6"); empty when there is none.
std::string samples_words(const SamplesNeeded& n, const std::string& name_a,
                          const std::string& name_b, bool pooled);

/// One pooled verdict as the estimate sees it: its series (verdicts that differ only in
/// rate), its rate, the relative cost of one sample of each set, and the sets' names.
struct ScatterSeries {
  std::size_t verdict = 0;  // its index in the verdicts
  int series = 0;
  double log10_rate = 0, cost_a = 1, cost_b = 1;
  std::string name_a = "A", name_b = "B";
};

/// Removes the estimate's words (samples_words, or margin.hpp's) from a reason.
void strip_samples_words(std::string& reason);

/// For every verdict listed in `series` with window scatter values (scatter_a, scatter_b,
/// samples_a, samples_b): the scatter pooled over its series' rates within one decade (values
/// scatter_a_pooled, scatter_b_pooled), and, when inconclusive, samples_needed (equal split, with
/// its words in the reason) and samples_needed_a, samples_needed_b (the cheapest split) from the
/// pooled scatter. `levels` and `margin` are those the verdicts were judged at.
void pool_window_scatter(std::vector<Verdict>& verdicts, const std::vector<ScatterSeries>& series,
                         Levels levels, double margin);

}  // namespace jam::checks
