#pragma once
// The statistic behind the finite-size and phi_init checks: the relative pressure difference
// of two run sets A and B on a common grid (the paper's supplement),
//   Delta_k = 2 (p_A - p_B) / (p_A + p_B),  sigma_k from the sample errors of both means,
// and a test that Delta is zero over the whole grid.
//
// Test: T = max_k |Delta_k| / sigma_k. Neighbouring grid points come from the same runs and
// are strongly correlated, so T's null distribution is not taken from a formula but obtained
// by permuting whole runs between A and B (exchangeable when there is no difference;
// checks/permutation.hpp: exact when the splits are few). Detected when T exceeds its
// threshold at levels.detect (the same rule as p <= levels.detect). The threshold c at
// 2 levels.pass gives a simultaneous band |Delta_k - true_k| <= c sigma_k, each sign at
// 1 - levels.pass, so
//   - the data exclude any effect larger than  max_k (|Delta_k| + c sigma_k)  (equivalence bound),
//   - and, with the threshold d at levels.detect (a simultaneous band at 1 - levels.detect),
//     any effect at or below  max_k (|Delta_k| - d sigma_k)  (the effect surely exceeds it
//     at some point: the bound a fail rests on),
//   - the smallest effect it could have detected is the detection threshold times the median
//     sigma_k.
#include <cstdint>
#include <vector>

#include "checks/permutation.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

/// The two error rates of one comparison. detect: the false-alarm rate of declaring a
/// difference (a check shares its alpha over its comparisons, Bonferroni, so that one false
/// "fail" in a whole check is at most alpha likely). pass: the false-pass rate of the
/// equivalence bound, one-sided for each sign (a two one-sided test, TOST, at level pass:
/// an effect beyond the margin passes with probability at most pass). A check passes when all
/// its verdicts pass, an intersection of tests that needs no share (intersection-union), so
/// pass is the check's alpha itself.
struct Levels {
  double detect = 0.05, pass = 0.025;
  /// One alpha for both, as a two-sided (1 - alpha) simultaneous band: the rule of the
  /// regression check and of the tests written for it.
  static Levels two_sided(double alpha) { return {alpha, alpha / 2}; }
};

/// What a relative difference is relative to: the mean of both sets, Delta_k = 2 (p_A - p_B) /
/// (p_A + p_B) (two sets on an equal footing: sizes, starts), or set B, Delta_k = (p_A - p_B) /
/// p_B (B a reference: the compare check's REF). sigma_k follows by first-order propagation of
/// both standard errors in either case.
enum class RelativeTo { mean, b };

/// How the null distribution was obtained, for the reason's words.
struct PermutationCount {
  int count = 0;
  bool exact = false;
  double splits = 0, smallest_p = 1;
};

struct RelativeDifference {
  std::vector<std::size_t> points;   // grid indices compared (finite and positive in both sets)
  std::vector<double> delta, sigma;  // per compared point
  double statistic = 0;              // T = max |Delta| / sigma
  double p_value = 1;                // permutation p-value of T
  double critical = 0;               // detection threshold: detected iff T > critical
  double band = 0;                   // c: the simultaneous band's half-width in sigmas
  double excluded_above = 0;         // max_k (|Delta_k| + c sigma_k)
  double excluded_below = 0;         // max(0, max_k (|Delta_k| - critical sigma_k))
  double detectable = 0;             // critical * median sigma_k
  PermutationCount permutations;
};

/// a, b: [sample][point] on the same grid (points where either table has NaN are dropped).
/// Deterministic for a given seed; `permutations` is the least number of random relabellings.
RelativeDifference compare_run_sets(const std::vector<std::vector<double>>& a,
                                    const std::vector<std::vector<double>>& b, Levels levels,
                                    int permutations = 2000, std::uint64_t seed = 1,
                                    RelativeTo to = RelativeTo::mean);

/// The same two run sets judged on one number, the window's weighted mean relative difference
///   D = sum_k w_k Delta_k,  w_k proportional to 1 / sigma_k^2
/// (sigma_k as above: within-set scatter, so a real difference does not lower the weight of
/// the points where it lies; recomputed on every permutation). These are the weights a
/// least-squares fit gives the points, so D is the shift of the pressure that a fit over the
/// window sees. Its null distribution again comes from permuting whole runs: detected when
/// |D| exceeds the threshold at levels.detect; with c the threshold of |D| at 2 levels.pass,
/// the data exclude any shift beyond |D| + c (each sign at 1 - levels.pass); with d the
/// threshold of |D| at 2 levels.detect, any shift at or below |D| - d (one-sided at
/// 1 - levels.detect: a fail that rests on it is false at most levels.detect of the time when
/// the true shift is at the bound, less when it is inside). A difference
/// confined to the noisiest points weighs little in D, as it does in a fit; the pointwise
/// bound of compare_run_sets is kept alongside (checks/pooled_verdict.hpp).
struct WeightedDifference {
  std::vector<std::size_t> points;
  std::vector<double> weight;  // w_k, summing to 1
  double difference = 0;       // D
  double p_value = 1;          // permutation p-value of |D|
  double critical = 0;         // detection threshold of |D|
  double band = 0;             // c
  double beyond = 0;           // d
  double excluded_above = 0;   // |D| + c
  double excluded_below = 0;   // max(0, |D| - d)
  PermutationCount permutations;
};
WeightedDifference compare_weighted(const std::vector<std::vector<double>>& a,
                                    const std::vector<std::vector<double>>& b, Levels levels,
                                    int permutations = 2000, std::uint64_t seed = 1,
                                    RelativeTo to = RelativeTo::mean);

/// Two sets of scalars (e.g. phi_Ji per run): T = |mean_a - mean_b| / sqrt(v_a/n_a + v_b/n_b),
/// p-value and thresholds from permuting the values between the sets (beyond: T's threshold
/// at 2 levels.detect, one-sided as for WeightedDifference). NaNs are dropped.
struct MeanDifference {
  double difference = 0, sigma = 0, statistic = 0, p_value = 1, critical = 0, band = 0;
  double beyond = 0;
  double excluded_above = 0, excluded_below = 0, detectable = 0;  // in the units of the values
  PermutationCount permutations;
};
MeanDifference compare_means(std::vector<double> a, std::vector<double> b, Levels levels,
                             int permutations = 2000, std::uint64_t seed = 1);

}  // namespace jam::checks
