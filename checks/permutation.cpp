#include "checks/permutation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace jam::checks {
namespace {

/// Exact enumeration is used up to this many splits even when fewer random relabellings would
/// do: an exact p-value has no Monte Carlo error, and 20000 evaluations cost well under a
/// second for the tables a check compares.
constexpr double kExactUpTo = 20000;

/// The statistic on each relabelling, given as the order of the pooled runs whose first n_a
/// form set A.
NullDistribution null_of(std::size_t n_a, std::size_t n_b,
                         const std::function<double(const std::vector<std::size_t>&)>& stat,
                         double alpha, int minimum, std::uint64_t seed) {
  NullDistribution d;
  d.splits = distinct_splits(n_a, n_b);
  const int wanted = permutations_for(alpha, minimum);
  const std::size_t n = n_a + n_b;
  std::vector<std::size_t> order(n);
  if (d.splits <= std::max<double>(wanted, kExactUpTo)) {
    d.exact = true;
    // Every subset of n_a members: a mask with n_a ones, stepped through its permutations.
    std::vector<char> in_a(n, 0);
    std::fill(in_a.begin(), in_a.begin() + static_cast<long>(n_a), 1);
    do {
      std::size_t ia = 0, ib = n_a;
      for (std::size_t i = 0; i < n; ++i) order[in_a[i] ? ia++ : ib++] = i;
      d.values.push_back(stat(order));
    } while (std::prev_permutation(in_a.begin(), in_a.end()));
  } else {
    std::iota(order.begin(), order.end(), 0);
    std::mt19937_64 rng(seed);
    d.values.reserve(static_cast<std::size_t>(wanted));
    for (int k = 0; k < wanted; ++k) {
      std::shuffle(order.begin(), order.end(), rng);
      d.values.push_back(stat(order));
    }
  }
  d.count = static_cast<int>(d.values.size());
  std::sort(d.values.begin(), d.values.end());
  return d;
}

/// The statistic of every relabelling of the members of a and b (rows or values).
template <class Member, class Stat>
NullDistribution relabelled(const std::vector<Member>& a, const std::vector<Member>& b,
                            const Stat& stat, double alpha, int minimum, std::uint64_t seed) {
  std::vector<Member> all = a;
  all.insert(all.end(), b.begin(), b.end());
  std::vector<Member> pa(a.size()), pb(b.size());
  return null_of(
      a.size(), b.size(),
      [&](const std::vector<std::size_t>& order) {
        for (std::size_t i = 0; i < all.size(); ++i)
          (i < a.size() ? pa[i] : pb[i - a.size()]) = all[order[i]];
        return stat(pa, pb);
      },
      alpha, minimum, seed);
}

}  // namespace

double distinct_splits(std::size_t n_a, std::size_t n_b) {
  // C(n, k) by the product formula in floating point: exact for the counts that are enumerated
  // (<= 2^53), and only compared with a budget beyond.
  const std::size_t n = n_a + n_b, k = std::min(n_a, n_b);
  double c = 1.0;
  for (std::size_t i = 1; i <= k; ++i)
    c = c * static_cast<double>(n - k + i) / static_cast<double>(i);
  return std::round(c);
}

int permutations_for(double alpha, int minimum) {
  const double wanted = std::ceil(20.0 / alpha);
  return static_cast<int>(std::min<double>(std::max<double>(minimum, wanted), 1e7));
}

double NullDistribution::p_value(double observed) const {
  const auto at_least =
      static_cast<double>(values.end() - std::lower_bound(values.begin(), values.end(), observed));
  // Exact: the observed split is one of those enumerated, so it counts at least itself.
  return exact ? std::max(at_least, 1.0) / count : (1.0 + at_least) / (1.0 + count);
}

double NullDistribution::threshold(double alpha) const {
  // Beyond every null value p is 1 / count (exact) or 1 / (1 + count): if even that exceeds
  // alpha, nothing can be detected.
  if (values.empty() || p_value(HUGE_VAL) > alpha) return std::numeric_limits<double>::infinity();
  // Walk down the groups of equal null values; p grows as the value falls. The first group
  // whose p exceeds alpha is the threshold.
  auto end = values.end();
  while (end != values.begin()) {
    const auto first = std::lower_bound(values.begin(), end, *(end - 1));
    if (p_value(*first) > alpha) return *first;
    end = first;
  }
  return -std::numeric_limits<double>::infinity();  // unreachable: p of the least value is 1
}

double NullDistribution::smallest_p() const {
  return values.empty() ? 1.0 : p_value(values.back());
}

NullDistribution permutation_null(const Rows& a, const Rows& b,
                                  const std::function<double(const Rows&, const Rows&)>& stat,
                                  double alpha, int minimum, std::uint64_t seed) {
  return relabelled(a, b, stat, alpha, minimum, seed);
}

NullDistribution permutation_null(
    const std::vector<double>& a, const std::vector<double>& b,
    const std::function<double(const std::vector<double>&, const std::vector<double>&)>& stat,
    double alpha, int minimum, std::uint64_t seed) {
  return relabelled(a, b, stat, alpha, minimum, seed);
}

}  // namespace jam::checks
