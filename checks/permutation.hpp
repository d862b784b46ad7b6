#pragma once
// The null distribution of a two-set statistic by relabelling whole runs, and the one rule that
// turns it into a p-value and a threshold.
//
// How many relabellings: every distinct split of the pooled runs into sets of the two sizes
// when there are few enough (exact enumeration: C(n_a + n_b, n_a) splits, the observed one
// among them), else random relabellings, at least `minimum` and at least 20 / alpha so that
// about 20 null values lie beyond the threshold (the Monte Carlo error of a p-value at alpha is
// then about 22% of alpha). The count and whether it was exact are kept for the verdict.
//
// One rule: p(t) = max(#{null >= t}, 1) / count (exact: the observed split is among those
// enumerated), (1 + #{null >= t}) / (1 + count) (random: the observed labelling counts once). The
// threshold at level alpha is the largest null value whose p exceeds alpha, so that
//   statistic > threshold   if and only if   p(statistic) <= alpha.
// When no null value reaches p <= alpha (4 against 4 runs have 70 splits, so no |D| p-value
// below 2/70), the threshold is infinite: nothing can be detected at that alpha, and the
// verdict says so instead of comparing with a quantile that cannot mean alpha.
#include <cstdint>
#include <functional>
#include <vector>

namespace jam::checks {

using Rows = std::vector<const std::vector<double>*>;

struct NullDistribution {
  std::vector<double> values;  // the statistic on every relabelling, sorted ascending
  bool exact = false;          // every distinct split enumerated
  double splits = 0;           // C(n_a + n_b, n_a): the distinct splits there are
  int count = 0;               // relabellings evaluated

  /// The p-value of an observed statistic (larger is more extreme).
  double p_value(double observed) const;
  /// The largest null value whose p-value exceeds alpha (+infinity when no statistic can
  /// reach p <= alpha): detected iff statistic > threshold.
  double threshold(double alpha) const;
  /// The smallest p-value any statistic can reach.
  double smallest_p() const;
};

/// The number of distinct splits of n_a + n_b runs into sets of n_a and n_b (as a double).
double distinct_splits(std::size_t n_a, std::size_t n_b);

/// The relabellings one comparison at level alpha needs: max(minimum, ceil(20 / alpha)).
int permutations_for(double alpha, int minimum);

/// The null distribution of stat(A, B) over relabellings of the rows of a and b (A keeps a's
/// size): exact when distinct_splits <= permutations_for(alpha, minimum) or <= 20000, else
/// random (deterministic in seed).
NullDistribution permutation_null(const Rows& a, const Rows& b,
                                  const std::function<double(const Rows&, const Rows&)>& stat,
                                  double alpha, int minimum, std::uint64_t seed);

/// The same for two sets of scalars.
NullDistribution permutation_null(
    const std::vector<double>& a, const std::vector<double>& b,
    const std::function<double(const std::vector<double>&, const std::vector<double>&)>& stat,
    double alpha, int minimum, std::uint64_t seed);

}  // namespace jam::checks
