// The zeta check (checks/zeta_check.cpp) on planted data: zeta = p / rate equal at the two
// slowest rates passes, a 30% difference fails, three noisy samples are inconclusive, and
// without the campaign's own fit (phi_J unknown) it says so instead of guessing.
#define BOOST_TEST_MODULE zeta_check
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

/// The statuses of the verdicts at packings on the grid (0.80 ... 0.859).
std::vector<std::string> statuses(const std::vector<Verdict>& v) {
  std::vector<std::string> out;
  for (const auto& x : v)
    if (x.values.at("phi") >= 0.80 - 1e-9) out.push_back(x.status);
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(converged_zeta_passes) {
  const auto v = zeta_check(two_rates(20, 0.0, 0.03, 1), CheckOptions{});
  BOOST_TEST(v.size() == 5u);  // one verdict per packing phi_J - 0.01 k
  for (const auto& s : statuses(v)) BOOST_TEST(s == "pass");
  for (const auto& x : v) BOOST_TEST(x.margin == 0.10);
}

BOOST_AUTO_TEST_CASE(rate_dependent_zeta_fails) {
  for (const auto& s : statuses(zeta_check(two_rates(20, 0.3, 0.03, 2), CheckOptions{})))
    BOOST_TEST(s == "fail");
}

BOOST_AUTO_TEST_CASE(too_few_noisy_samples_are_inconclusive) {
  for (const auto& s : statuses(zeta_check(two_rates(3, 0.0, 0.3, 3), CheckOptions{})))
    BOOST_TEST(s == "inconclusive");
}

BOOST_AUTO_TEST_CASE(without_the_campaigns_fit_it_does_not_guess) {
  StatsData d = two_rates(20, 0.0, 0.03, 4);
  d.fit_phi_j.reset();
  const auto v = zeta_check(d, CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 1u);
  BOOST_TEST(v[0].status == "inconclusive");
  BOOST_TEST(v[0].reason.find("never the paper's value") != std::string::npos);
}
