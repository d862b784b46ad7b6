#pragma once
// Three outcomes against a margin M (checks/verdict.hpp), for every statistical check, by the
// same two one-sided logic on either side of the margin:
//   pass          excluded_above <= M: every effect the data allow at 1 - alpha lies in +-M,
//   fail          excluded_below > M: the data exclude every effect at or below M (one-sided
//                 at the detection level), so the effect surely exceeds the margin,
//   inconclusive  neither; when a difference is detected (p <= alpha) but not shown to exceed
//                 M, the reason says so with the estimate and the effects allowed.
// A test that is not significant never passes by itself: "found no difference" means nothing
// unless the data also exclude every difference beyond the margin. And a detected difference
// never fails by itself: "different" is not "different by more than the margin".
//
// samples_needed (inconclusive only) is an estimate of the samples per set that would decide
// the comparison at the observed scatter, standard errors shrinking as 1/sqrt(samples) and the
// thresholds held. Where every observed |Delta_k| < M, the difference is taken for noise
// (nothing was detected) and the whole bound shrinks: pass at  n (excluded_above / M)^2.
// Otherwise the observed difference beyond M is taken for the truth, and it would be shown to
// exceed M at  n min over those k of (detection threshold_k / (|Delta_k| - M))^2.
#include <string>
#include <vector>

#include "checks/relative_difference.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

/// The outcome from a detection at alpha, the equivalence bound excluded_above and the lower
/// bound excluded_below (the effect surely exceeds it), with the words of the reason (sets
/// v.status, v.reason, v.margin, v.excluded_above, v.excluded_below).
void decide(Verdict& v, bool detected, double excluded_above, double excluded_below, double margin);

/// Judges v on a relative difference of run sets with `samples` per set (the smaller set).
void judge(Verdict& v, const RelativeDifference& t, Levels levels, double margin,
           std::size_t samples);

/// Judges v on the weighted mean relative difference of two run sets (statistic |D|,
/// threshold: its detection threshold) with `samples` per set.
void judge(Verdict& v, const WeightedDifference& t, Levels levels, double margin,
           std::size_t samples);

/// Judges v on a difference of means (units of the values) with `samples` per set.
void judge(Verdict& v, const MeanDifference& t, Levels levels, double margin, std::size_t samples);

/// Delta p/p of two run sets on one grid (stats_data.hpp, align) judged against the margin;
/// the verdict keeps the curves compared (grid, delta, sigma). Throws std::invalid_argument
/// as compare_run_sets does.
RelativeDifference judge_curves(Verdict& v, const Aligned& al, Levels levels, double margin,
                                int permutations);

/// The samples-per-set estimate above for per-point differences and their bands (band_k:
/// the half-width of the equivalence band at point k).
double samples_to_decide(const std::vector<double>& delta, const std::vector<double>& band,
                         const std::vector<double>& detect, double margin, std::size_t samples);

/// How the permutation test was run and what it can reach, in words for a reason:
/// "p = 0.012, alpha 0.0014, all 70 splits of whole runs; no p-value below 0.029 is reachable".
std::string permutation_words(double p_value, double alpha, const PermutationCount& c);

/// The first index of a pressure curve that the compression, not the start, sets: the first
/// grid point after the start (index 0, t = 0) whose mean pressure is at least
/// kTransientFactor times the start's (checks/margin.cpp says why). Returns the curve's size
/// when there is none.
constexpr double kTransientFactor = 10.0;
std::size_t first_compression_point(const std::vector<std::vector<double>>& samples);

/// The start's transient the pointwise rule never judges: kStartTransient in packing past the
/// first compressed point. Past the 10x rule the start no longer sets the pressure, but the
/// contact network a relaxed start had is still being rebuilt by the flow: 2D N = 64 against
/// 1024 from phi_init 0.80 at rate 1e-6 differed pointwise only at phi 0.802 among the points
/// before jamming, and its sizes agree within errors from 0.805 to 0.82 (docs/statistics-and-
/// checks.md, "Real finite-size effects"). The pooled verdicts still weigh these points.
constexpr double kStartTransient = 0.005;

/// The same for a chained start, which carries the pressure of the faster rate it was taken
/// from: the first point after the mean pressure stops falling (checks/margin.cpp says why).
std::size_t first_chained_compression_point(const std::vector<std::vector<double>>& samples);

}  // namespace jam::checks
