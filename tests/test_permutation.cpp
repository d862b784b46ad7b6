// The permutation rule (checks/permutation.hpp): exact enumeration when the splits are few,
// one rule for the p-value and the threshold (a statistic above its threshold is detected,
// never "no difference detected"), and the honest words when too few splits make alpha
// unreachable.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/margin.hpp"
#include "checks/permutation.hpp"
#include "checks/relative_difference.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

BOOST_AUTO_TEST_CASE(distinct_splits_are_binomial_coefficients) {
  BOOST_TEST(distinct_splits(4, 4) == 70.0);
  BOOST_TEST(distinct_splits(10, 10) == 184756.0);
  BOOST_TEST(distinct_splits(3, 5) == 56.0);
  BOOST_TEST(permutations_for(0.05 / 36, 2000) == 14400);  // 20 / alpha
  BOOST_TEST(permutations_for(0.05, 2000) == 2000);
}

BOOST_AUTO_TEST_CASE(few_splits_are_enumerated_exactly) {
  // 4 against 4 scalars: every one of the 70 splits, the observed one among them.
  const std::vector<double> a{1, 2, 3, 4}, b{5, 6, 7, 8};
  auto diff = [](const std::vector<double>& x, const std::vector<double>& y) {
    double s = 0;
    for (double v : x) s += v;
    for (double v : y) s -= v;
    return std::abs(s);
  };
  const NullDistribution d = permutation_null(a, b, diff, 0.05, 100, 1);
  BOOST_TEST(d.exact);
  BOOST_TEST(d.count == 70);
  // The observed split is the most extreme, shared with its mirror image: p = 2/70 exactly.
  BOOST_TEST(d.p_value(diff(a, b)) == 2.0 / 70.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(d.smallest_p() == 2.0 / 70.0, boost::test_tools::tolerance(1e-15));
  // alpha 0.05 is reachable, a Bonferroni alpha of 0.0014 is not: the threshold is infinite.
  BOOST_TEST(diff(a, b) > d.threshold(0.05));
  BOOST_TEST(std::isinf(d.threshold(0.05 / 36)));
}

BOOST_AUTO_TEST_CASE(statistic_above_threshold_iff_p_at_most_alpha) {
  // Over many null distributions with ties (rounded values) and observations on and between
  // null values, random and exact: the two rules never disagree.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    NullDistribution d;
    d.exact = trial % 2 == 0;
    const int count = 20 + trial;
    for (int k = 0; k < count; ++k) d.values.push_back(std::round(u(rng) * 10) / 10);
    std::sort(d.values.begin(), d.values.end());
    d.count = count;
    for (double alpha : {0.01, 0.05, 0.1, 0.3}) {
      const double c = d.threshold(alpha);
      for (double t = -0.05; t < 1.1; t += 0.05) {
        BOOST_TEST((t > c) == (d.p_value(t) <= alpha),
                   "t " << t << " c " << c << " alpha " << alpha);
        ++checked;
      }
    }
  }
  BOOST_TEST(checked > 10000);
}

BOOST_AUTO_TEST_CASE(unreachable_alpha_is_said_not_hidden) {
  // Four samples against four with a large planted difference, at a Bonferroni alpha no split
  // can reach: inconclusive, with the words, never a statistic above an unmet threshold.
  std::mt19937_64 rng(6);
  const auto a = runs(4, 0.5, rng), b = runs(4, 0.0, rng);
  const Levels levels{0.05 / 36, 0.05};
  const WeightedDifference w = compare_weighted(a, b, levels, 2000, 1);
  BOOST_TEST(w.permutations.exact);
  BOOST_TEST(w.permutations.count == 70);
  BOOST_TEST(std::isinf(w.critical));
  Verdict v;
  judge(v, w, levels, 0.1, 4);
  BOOST_TEST(v.status == "inconclusive");
  BOOST_TEST(v.reason.find("all 70 splits") != std::string::npos, v.reason);
  BOOST_TEST(v.reason.find("no p-value below 0.0286 is reachable") != std::string::npos, v.reason);
  BOOST_TEST(std::isfinite(v.samples_needed));
  // At alpha 0.05 the same data are detected, and the rule agrees with the p-value.
  const WeightedDifference x = compare_weighted(a, b, Levels{0.05, 0.05}, 2000, 1);
  BOOST_TEST((std::abs(x.difference) > x.critical) == (x.p_value <= 0.05));
  BOOST_TEST(x.p_value <= 0.05);
}
