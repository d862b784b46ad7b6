// The chain check (checks/chain_check.cpp) on planted data: a chained rate equal to its
// unchained control passes, one 30% off fails, a memory confined to the window's first points
// fails, three noisy samples are inconclusive, and without a control it says so. The weighted
// comparison it judges on (compare_weighted) has its false-alarm and false-pass rates
// measured. The chained start's transient (margin.cpp, first_chained_compression_point) ends
// after the pressure's minimum.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/regression_check.hpp"
#include "checks/relative_difference.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

struct Pair {
  StatsData chained, control;
};

/// The chained rate 1e-6 (from 0.80) of one (N, phi_init), and the same samples unchained.
Pair chained_and_control(int samples, double shift, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Pair p;
  p.chained.ensembles.push_back(ensemble(256, 0.4, -6.0, runs(samples, shift, rng, 60, amplitude)));
  p.chained.ensembles.back().chain_phi_init = 0.80;
  p.control.ensembles.push_back(ensemble(256, 0.4, -6.0, runs(samples, 0.0, rng, 60, amplitude)));
  return p;
}

std::vector<Verdict> check(const Pair& p) {
  return chain_check(p.chained, p.control, CheckOptions{}, RegressionOptions{});
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_chain_that_is_forgotten_passes) {
  const auto v = check(chained_and_control(20, 0.0, 0.03, 1));
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "pass", v[0].reason);
  BOOST_TEST(v[0].margin == 0.10);
  BOOST_TEST(v[0].values.at("chain_phi_init") == 0.80);
}

BOOST_AUTO_TEST_CASE(a_remembered_chain_fails) {
  const auto v = check(chained_and_control(20, 0.3, 0.03, 2));
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "fail", v[0].reason);
}

BOOST_AUTO_TEST_CASE(a_memory_at_the_window_edge_fails_although_the_mean_is_small) {
  // +60% at the first point, decaying over 3 points (the measured chained excess one output
  // point after phi'_init was +43-67%): the weighted mean over 60 points stays within the
  // margin, the points themselves do not.
  Pair p = chained_and_control(20, 0.0, 0.03, 6);
  for (auto& run : p.chained.ensembles.front().pressure_at_phi)
    for (std::size_t k = 0; k < run.size(); ++k) run[k] *= 1.0 + 0.6 * std::exp(-double(k) / 3.0);
  const auto v = check(p);
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "fail", v[0].reason);
  BOOST_TEST(v[0].reason.find("surely exceeds") != std::string::npos, v[0].reason);
}

BOOST_AUTO_TEST_CASE(too_few_noisy_samples_are_inconclusive) {
  const auto v = check(chained_and_control(3, 0.0, 0.3, 3));
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "inconclusive", v[0].reason);
}

BOOST_AUTO_TEST_CASE(without_a_control_it_says_so) {
  Pair p = chained_and_control(20, 0.0, 0.03, 4);
  p.control.ensembles.front().log10_rate = -5.0;  // another rate: no control for 1e-6
  const auto v = check(p);
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "inconclusive");
  BOOST_TEST(v[0].reason.find("no chained rate") != std::string::npos);
  // An unchained campaign has nothing to justify either.
  p = chained_and_control(20, 0.0, 0.03, 5);
  p.chained.ensembles.front().chain_phi_init = 0;
  BOOST_TEST(check(p).front().status == "inconclusive");
}

BOOST_AUTO_TEST_CASE(the_chained_transient_ends_after_the_pressure_minimum) {
  // The faster rate's pressure decays (10, 6, 4, 3.5) before the compression's rise (3.6...).
  const std::vector<std::vector<double>> p = {{10, 6, 4, 3.5, 3.6, 3.8, 4.2},
                                              {12, 7, 4.4, 3.3, 3.4, 3.9, 4.4}};
  BOOST_TEST(first_chained_compression_point(p) == 4u);
  // The relaxed-start rule would have dropped everything (never 10x the start's pressure).
  BOOST_TEST(first_compression_point(p) == 7u);
  const std::vector<std::vector<double>> falling = {{5, 4, 3, 2}};
  BOOST_TEST(first_chained_compression_point(falling) == 4u);  // not past it: nothing compared
}

BOOST_AUTO_TEST_CASE(weighted_comparison_false_alarm_and_false_pass_rates) {
  // False alarms: two sets from one distribution (10 samples, 10% scatter), 400 repeats at
  // alpha 0.05: the fraction detected must be near 0.05 (binomial sd 0.011; accept 0.02-0.09).
  std::mt19937_64 rng(7);
  const int repeats = 400;
  int alarms = 0, passes_null = 0;
  for (int r = 0; r < repeats; ++r) {
    const WeightedDifference w =
        compare_weighted(runs(10, 0.0, rng), runs(10, 0.0, rng), Levels::two_sided(0.05), 400,
                         100 + static_cast<unsigned>(r));
    alarms += w.p_value <= 0.05;
    passes_null += w.excluded_above <= 0.10;
  }
  BOOST_TEST_MESSAGE("weighted: false-alarm rate " << double(alarms) / repeats
                                                   << ", pass rate without effect at margin 0.1 "
                                                   << double(passes_null) / repeats);
  BOOST_TEST(double(alarms) / repeats > 0.02);
  BOOST_TEST(double(alarms) / repeats < 0.09);
  // Power: without an effect these data pass a 10% margin nearly always (D's scatter is about
  // 0.025 here: 10 samples, 60 points, neighbour correlation 0.9).
  BOOST_TEST(double(passes_null) / repeats > 0.9);
  // False passes: a true shift of 12% (Delta p/p = 0.113) just beyond the 10% margin may pass
  // at most at the rate of the band's one-sided miss, alpha / 2 = 0.025 (accept < 0.06).
  int false_passes = 0;
  for (int r = 0; r < repeats; ++r) {
    const WeightedDifference w =
        compare_weighted(runs(10, 0.12, rng), runs(10, 0.0, rng), Levels::two_sided(0.05), 400,
                         900 + static_cast<unsigned>(r));
    false_passes += w.excluded_above <= 0.10;
  }
  BOOST_TEST_MESSAGE(
      "weighted: false-pass rate at a 12% shift, margin 0.1: " << double(false_passes) / repeats);
  BOOST_TEST(double(false_passes) / repeats < 0.06);
}

BOOST_AUTO_TEST_CASE(weights_follow_the_scatter) {
  // Points twice as noisy weigh about four times less; weights sum to one.
  std::mt19937_64 rng(8);
  auto a = runs(200, 0.0, rng, 20, 0.05), b = runs(200, 0.0, rng, 20, 0.05);
  std::normal_distribution<double> g(0.0, 0.1);
  for (auto* set : {&a, &b})
    for (auto& run : *set)
      for (std::size_t k = 10; k < 20; ++k) run[k] *= std::exp(g(rng));  // 5% -> ~11% scatter
  const WeightedDifference w = compare_weighted(a, b, Levels::two_sided(0.05), 200);
  double sum = 0, quiet = 0, noisy = 0;
  for (std::size_t k = 0; k < w.weight.size(); ++k) {
    sum += w.weight[k];
    (k < 10 ? quiet : noisy) += w.weight[k];
  }
  BOOST_TEST(sum == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(quiet / noisy > 3.0);
  BOOST_TEST(quiet / noisy < 7.0);
}
