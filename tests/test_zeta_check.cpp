// The zeta check (checks/zeta_check.cpp) on planted data: zeta = p / rate equal at the two
// slowest rates passes, a 30% difference fails, three noisy samples are inconclusive, and
// without the campaign's own fit (phi_J unknown) it says so instead of guessing.
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "checks/checks.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

/// Two rates of one (N, phi_init): p = rate * zeta, zeta of the faster rate shifted by `shift`.
StatsData two_rates(int samples, double shift, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  StatsData d;
  d.fit_phi_j = 0.84;
  for (auto [log10_rate, s] : {std::pair{-6.0, 0.0}, std::pair{-5.5, shift}}) {
    auto p = runs(samples, s, rng, 60, amplitude);
    for (auto& row : p)
      for (double& x : row) x *= std::pow(10.0, log10_rate);
    d.ensembles.push_back(ensemble(1024, 0.8, log10_rate, std::move(p)));
  }
  return d;
}

}  // namespace

BOOST_AUTO_TEST_CASE(converged_zeta_passes) {
  const auto v = zeta_check(two_rates(20, 0.0, 0.03, 1), CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 1u);  // one verdict per (N, phi_init), pooled below phi_J
  BOOST_TEST(v[0].status == "pass", v[0].reason);
  BOOST_TEST(v[0].margin == 0.10);
  // Pooled over phi_J - 0.05 ... phi_J - 0.01, cut to the grid (0.800 ... 0.859).
  BOOST_TEST(v[0].values.at("range_min") == 0.80, boost::test_tools::tolerance(1e-9));
  BOOST_TEST(v[0].values.at("range_max") == 0.83, boost::test_tools::tolerance(1e-9));
}

BOOST_AUTO_TEST_CASE(rate_dependent_zeta_fails) {
  const auto v = zeta_check(two_rates(20, 0.3, 0.03, 2), CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "fail", v[0].reason);
}

BOOST_AUTO_TEST_CASE(too_few_noisy_samples_are_inconclusive) {
  const auto v = zeta_check(two_rates(3, 0.0, 0.3, 3), CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "inconclusive", v[0].reason);
}

BOOST_AUTO_TEST_CASE(without_the_campaigns_fit_it_does_not_guess) {
  StatsData d = two_rates(20, 0.0, 0.03, 4);
  d.fit_phi_j.reset();
  const auto v = zeta_check(d, CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "inconclusive");
  BOOST_TEST(v[0].reason.find("never the paper's value") != std::string::npos);
}
