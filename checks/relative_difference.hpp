#pragma once
// The statistic behind the finite-size and phi_init checks: the relative pressure difference
// of two run sets A and B on a common grid (the paper's supplement),
//   Delta_k = 2 (p_A - p_B) / (p_A + p_B),  sigma_k from the sample errors of both means,
// and a test that Delta is zero over the whole grid.
//
// Test: T = max_k |Delta_k| / sigma_k. Neighbouring grid points come from the same runs and
// are strongly correlated, so T's null distribution is not taken from a formula but obtained
// by permuting whole runs between A and B (exchangeable when there is no difference): the
// p-value is the fraction of label permutations with T >= T_observed. The (1 - alpha)
// quantile c of that distribution gives a simultaneous band |Delta_k - true_k| <= c sigma_k, so
//   - the data exclude any effect larger than  max_k (|Delta_k| + c sigma_k)  (equivalence bound),
//   - the smallest effect it could have detected is c times the median sigma_k.
#include <cstdint>
#include <vector>

#include "checks/verdict.hpp"

namespace jam::checks {

struct RelativeDifference {
  std::vector<std::size_t> points;   // grid indices compared (finite and positive in both sets)
  std::vector<double> delta, sigma;  // per compared point
  double statistic = 0;              // T = max |Delta| / sigma
  double p_value = 1;                // permutation p-value of T
  double critical = 0;               // c, the (1 - alpha) quantile of T under permutation
  double excluded_above = 0;         // max_k (|Delta_k| + c sigma_k)
  double detectable = 0;             // c * median sigma_k
  int permutations = 0;
};

/// a, b: [sample][point] on the same grid (points where either table has NaN are dropped).
/// alpha: the false-alarm rate of this one comparison. Deterministic for a given seed.
RelativeDifference compare_run_sets(const std::vector<std::vector<double>>& a,
                                    const std::vector<std::vector<double>>& b, double alpha,
                                    int permutations = 2000, std::uint64_t seed = 1);

/// The same two run sets judged on one number, the window's weighted mean relative difference
///   D = sum_k w_k Delta_k,  w_k proportional to 1 / sigma_k^2
/// (sigma_k as above: within-set scatter, so a real difference does not lower the weight of
/// the points where it lies; recomputed on every permutation). These are the weights a
/// least-squares fit gives the points, so D is the shift of the pressure that a fit over the
/// window sees. Its null distribution again comes from permuting whole runs: c is the
/// (1 - alpha) quantile of |D| there, the data exclude any shift beyond |D| + c and could have
/// detected one of c. A difference confined to the noisiest points weighs little in D, as it
/// does in a fit; the pointwise bound of compare_run_sets is kept alongside.
struct WeightedDifference {
  std::vector<std::size_t> points;
  std::vector<double> weight;  // w_k, summing to 1
  double difference = 0;       // D
  double p_value = 1;          // permutation p-value of |D|
  double critical = 0;         // c
  double excluded_above = 0;   // |D| + c
  int permutations = 0;
};
WeightedDifference compare_weighted(const std::vector<std::vector<double>>& a,
                                    const std::vector<std::vector<double>>& b, double alpha,
                                    int permutations = 2000, std::uint64_t seed = 1);

/// Two sets of scalars (e.g. phi_Ji per run): T = |mean_a - mean_b| / sqrt(v_a/n_a + v_b/n_b),
/// p-value and critical value from permuting the values between the sets. NaNs are dropped.
struct MeanDifference {
  double difference = 0, sigma = 0, statistic = 0, p_value = 1, critical = 0;
  double excluded_above = 0, detectable = 0;  // in the units of the values
};
MeanDifference compare_means(std::vector<double> a, std::vector<double> b, double alpha,
                             int permutations = 2000, std::uint64_t seed = 1);

}  // namespace jam::checks
