// The chain check (checks/chain_check.cpp) on planted data: a chained rate equal to its
// unchained control passes, one 30% off fails, three noisy samples are inconclusive, and
// without a control it says so. The chained start's transient (margin.cpp,
// first_chained_compression_point) ends after the pressure's minimum.
#define BOOST_TEST_MODULE chain_check
#include <boost/test/unit_test.hpp>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/regression_check.hpp"
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
