// The pooled verdict of the pressure checks (checks/pooled_verdict.hpp) at the reduced-2d
// design, 10 samples per set and 36 comparisons sharing alpha 0.05 (Bonferroni for
// detection; each pass a two one-sided test at 0.05), measured on planted synthetic sets:
// power to fail effects beyond the margin, the false-fail rate of effects within it, the
// false-alarm rate without an effect, and the false-pass rate of 1.2 x the margin. The data: synthetic_runs.hpp (10% scatter per run, AR(1)
// correlation 0.9 along 60 grid points).
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/pooled_verdict.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

constexpr double kMargin = 0.10;

/// The verdict on two synthetic sets of `samples` runs, the first shifted by `shift`.
Verdict judged(double shift, Levels levels, int samples, std::uint64_t seed, int permutations,
               double scatter = 0.1) {
  std::mt19937_64 rng(seed);
  const auto a = runs(samples, shift, rng, 60, scatter), b = runs(samples, 0.0, rng, 60, scatter);
  Aligned al;
  for (std::size_t k = 0; k < a.front().size(); ++k) al.grid.push_back(0.80 + 0.001 * k);
  al.a = a;
  al.b = b;
  PoolRange range;
  range.why = "the synthetic grid";
  Verdict v;
  judge_pooled(v, al, range, levels, kMargin, permutations, seed);
  return v;
}

/// The one-sided 95% allowance of a rate measured as k of n around its nominal value.
double binomial_slack(double rate, int n) {
  return 1.645 * std::sqrt(rate * (1 - rate) / n);
}

}  // namespace

// A fail needs the data to exclude every effect at or below the margin: |D| - d > M, d the
// one-sided threshold at the detection level (0.05/36 here: about 3.0 sigma_D). An effect
// fails with power 0.8 from about M + (3.0 + 0.84) sigma_D. With 2.5% scatter per run and 10
// samples per set (sigma_D about 0.011) 1.5 M is within reach: required >= 0.8 over 60
// repeats.
BOOST_AUTO_TEST_CASE(an_effect_of_one_and_a_half_margins_fails_where_the_data_can_show_it) {
  const Levels levels{0.05 / 36, 0.05};
  const double delta = 1.5 * kMargin, shift = 2 * delta / (2 - delta);
  int failed = 0;
  const int repeats = 60;
  for (int r = 0; r < repeats; ++r)
    failed += judged(shift, levels, 10, 100 + static_cast<unsigned>(r), 400, 0.025).status ==
              "fail";
  BOOST_TEST_MESSAGE("power to fail 1.5 x the margin, 2.5% scatter: " << double(failed) / repeats);
  BOOST_TEST(double(failed) / repeats >= 0.8);
}

BOOST_AUTO_TEST_CASE(power_at_the_reduced_design_is_measured_not_assumed) {
  // 10 samples per set at 10% scatter (sigma_D about 0.043): the power curve the docs quote
  // (docs/statistics-and-checks.md). Only its shape is asserted: more effect, more fails, and
  // 3 M nearly always (0.2 beyond the margin is 4.6 sigma_D).
  const Levels levels{0.05 / 36, 0.05};
  std::vector<double> power;
  for (double times : {1.5, 2.0, 3.0}) {
    const double delta = times * kMargin, shift = 2 * delta / (2 - delta);
    int failed = 0;
    for (int r = 0; r < 40; ++r)
      failed += judged(shift, levels, 10, 300 + static_cast<unsigned>(r), 400).status == "fail";
    power.push_back(failed / 40.0);
    BOOST_TEST_MESSAGE("power to fail " << times << " x the margin, 10 samples per set: "
                                        << power.back());
  }
  BOOST_TEST(power[0] <= power[1]);
  BOOST_TEST(power[1] <= power[2]);
  BOOST_TEST(power[2] >= 0.85);
}

BOOST_AUTO_TEST_CASE(an_effect_within_the_margin_fails_at_most_alpha) {
  // The false-fail rate against "the effect is within the margin": at an effect of exactly M
  // the fail rule is a one-sided test at the detection level (0.05 here, to be measurable in
  // 300 repeats): at most 0.05 plus the binomial allowance; inside the margin far less.
  const Levels levels{0.05, 0.05};
  for (double times : {0.5, 0.8, 1.0}) {
    const double delta = times * kMargin, shift = 2 * delta / (2 - delta);
    int fails = 0;
    const int repeats = 300;
    for (int r = 0; r < repeats; ++r)
      fails += judged(shift, levels, 10, 9000 + static_cast<unsigned>(r), 200).status == "fail";
    const double rate = double(fails) / repeats;
    BOOST_TEST_MESSAGE("false-fail rate at " << times << " x the margin: " << rate);
    BOOST_TEST(rate <= 0.05 + binomial_slack(0.05, repeats));
  }
}

BOOST_AUTO_TEST_CASE(an_eight_percent_effect_never_fails_a_ten_percent_margin) {
  // The case a user met: 8% at 4% scatter per run, 10 samples per set, margin 10%. The effect
  // is detected, often, but lies inside the margin: inconclusive or pass, never fail.
  const Levels levels{0.05 / 36, 0.05};
  const double shift = 2 * 0.08 / (2 - 0.08);
  int fails = 0, detected = 0;
  for (int r = 0; r < 100; ++r) {
    std::mt19937_64 rng(20000 + r);
    Aligned al;
    al.a = runs(10, shift, rng, 60, 0.04);
    al.b = runs(10, 0.0, rng, 60, 0.04);
    for (std::size_t k = 0; k < 60; ++k) al.grid.push_back(0.80 + 0.001 * k);
    PoolRange range;
    Verdict v;
    judge_pooled(v, al, range, levels, kMargin, 400, r);
    fails += v.status == "fail";
    detected += v.statistic > v.threshold;
    if (v.status == "inconclusive" && v.statistic > v.threshold)
      BOOST_TEST(v.reason.starts_with("a difference is detected, not shown to exceed the margin"),
                 v.reason);
  }
  BOOST_TEST_MESSAGE("8% at 10%: detected " << detected << " of 100, failed " << fails);
  BOOST_TEST(fails == 0);
  BOOST_TEST(detected > 50);  // the test has power: the effect is seen, and still not failed
}

BOOST_AUTO_TEST_CASE(false_alarm_rate_is_alpha) {
  // No effect, 300 repeats at a detection level of 0.05 (the rule is the same at every level;
  // 0.05 makes the rate measurable in 300 repeats): failures at most 0.05 plus the binomial
  // allowance (0.021). Most verdicts pass: D's bound lies well within 0.1 at this scatter.
  const Levels levels{0.05, 0.05};
  int alarms = 0, passes = 0;
  const int repeats = 300;
  for (int r = 0; r < repeats; ++r) {
    const Verdict v = judged(0.0, levels, 10, 1000 + static_cast<unsigned>(r), 400);
    alarms += v.statistic > v.threshold;
    passes += v.status == "pass";
  }
  const double rate = double(alarms) / repeats;
  BOOST_TEST_MESSAGE("false-alarm rate at 0.05: " << rate << ", pass rate "
                                                  << double(passes) / repeats);
  BOOST_TEST(rate <= 0.05 + binomial_slack(0.05, repeats));
  BOOST_TEST(rate > 0.01);  // and the test is not dead
  BOOST_TEST(double(passes) / repeats > 0.9);
}

BOOST_AUTO_TEST_CASE(an_effect_beyond_the_margin_rarely_passes) {
  // A true Delta p/p of 1.2 x the margin (a shift of 12.8%): passes at most 5% of the time
  // (the two one-sided tests at 0.05), plus the binomial allowance, over 300 repeats.
  // Delta p/p = 2 s / (2 + s) for a shift s. The pass rule does not depend on the detection
  // level, which is 0.05 here to keep the permutations few.
  const double delta = 1.2 * kMargin, shift = 2 * delta / (2 - delta);
  const Levels levels{0.05, 0.05};
  int passes = 0;
  const int repeats = 300;
  for (int r = 0; r < repeats; ++r)
    passes += judged(shift, levels, 10, 5000 + static_cast<unsigned>(r), 200).status == "pass";
  const double rate = double(passes) / repeats;
  BOOST_TEST_MESSAGE("false-pass rate at 1.2 x margin: " << rate);
  BOOST_TEST(rate <= 0.05 + binomial_slack(0.05, repeats));
}

BOOST_AUTO_TEST_CASE(verdict_states_its_range_and_where_the_weights_lie) {
  const Verdict v = judged(0.0, Levels{0.05, 0.05}, 10, 7, 400);
  BOOST_TEST(v.values.at("range_min") == 0.80, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(v.values.at("range_max") == 0.859, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(v.values.at("weight_from") <= v.values.at("weighted_at"));
  BOOST_TEST(v.values.at("weighted_at") <= v.values.at("weight_to"));
  BOOST_TEST(v.reason.find("the synthetic grid") != std::string::npos, v.reason);
  BOOST_TEST(v.reason.find("80% of them in") != std::string::npos, v.reason);
}

// A span with no finite ends (no Z of both sets whose mean packing lies in the window asked:
// z_span gives [inf, -inf]) is said in words, never as "[inf, -inf]" or "from inf".
BOOST_AUTO_TEST_CASE(an_empty_span_is_said_in_words) {
  std::mt19937_64 rng(3);
  Aligned al;
  al.a = runs(6, 0.0, rng, 60, 0.1);
  al.b = runs(6, 0.0, rng, 60, 0.1);
  for (std::size_t k = 0; k < al.a.front().size(); ++k) al.grid.push_back(4.0 + 0.01 * k);
  PoolRange pooled;
  pooled.variable = "Z";
  pooled.min = HUGE_VAL, pooled.max = -HUGE_VAL;
  pooled.why = "the Z whose mean packing lies in the scaling fit's window";
  Verdict base;
  base.check = "finite_size";
  const auto out = judge_by_region(base, al, pooled, {}, {}, Levels{0.05, 0.05}, kMargin, 100, 1,
                                   RelativeTo::b);
  BOOST_TEST_REQUIRE(!out.empty());
  for (const Verdict& v : out) {
    BOOST_TEST(v.status == "inconclusive");
    BOOST_TEST(v.reason.find("inf") == std::string::npos, v.reason);
    BOOST_TEST(v.reason.find("no Z of both sets lies in") != std::string::npos, v.reason);
  }
}
