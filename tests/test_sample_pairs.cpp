// The sample_pairs check's null (checks/sample_pairs_check.cpp) keeps each size's own scatter:
// two sizes with the same mean pressure, one scattering six times more than the other, are
// not a detection (the former null, relabelling runs between the sizes, detected exactly this
// with hundreds of samples), while a 15% systematic difference is.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/checks.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

/// The verdict on N = 128 against N = 1024 (`scatter_a`, `scatter_b`: per run), `samples`
/// each, the smaller size shifted by `shift`.
Verdict judged(double shift, int samples, double scatter_a, double scatter_b,
               std::mt19937_64& rng) {
  StatsData d;
  d.ensembles.push_back(ensemble(128, 0.4, -6, runs(samples, shift, rng, 60, scatter_a)));
  d.ensembles.push_back(ensemble(1024, 0.4, -6, runs(samples, 0.0, rng, 60, scatter_b)));
  CheckOptions o;
  o.margins["sample_pairs"] = 0.1;
  const auto v = sample_pairs_check(d, o);
  BOOST_REQUIRE(v.size() == 1);
  return v.front();
}

}  // namespace

// 60% against 10% scatter (as N = 128 and 1024 near jamming at slow rates), 200 samples each,
// 50 repeats at alpha 0.05: the detection rate must stay within alpha plus its one-sided 95%
// binomial allowance (1.645 sqrt(0.05 0.95 / 50) = 0.051), at most 5 of 50. The former null
// detected 50 of 50 (measured 100 of 100 over 100 repeats).
BOOST_AUTO_TEST_CASE(unequal_scatter_is_no_difference) {
  std::mt19937_64 rng(21);
  int detected = 0;
  const int repeats = 50;
  for (int r = 0; r < repeats; ++r) {
    const Verdict v = judged(0.0, 200, 0.6, 0.1, rng);
    detected += v.statistic > v.threshold;
  }
  BOOST_TEST_MESSAGE("detected " << detected << " of " << repeats);
  BOOST_TEST(detected <= 5);
}

// A 15% systematic difference at 20% and 5% scatter (R = 1 + 0.15^2 / (0.2^2 + 0.05^2) ~ 1.5
// with 60 pairs) is detected in at least 18 of 20 repeats.
BOOST_AUTO_TEST_CASE(a_systematic_difference_is_detected) {
  std::mt19937_64 rng(22);
  int detected = 0;
  for (int r = 0; r < 20; ++r) {
    const Verdict v = judged(0.15, 60, 0.2, 0.05, rng);
    detected += v.statistic > v.threshold;
  }
  BOOST_TEST_MESSAGE("detected " << detected << " of 20");
  BOOST_TEST(detected >= 18);
}
