// The fit_parameters check (checks/fit_parameters_check.cpp) on planted fitted parameters:
// equal parameters with small errors pass, beta 30% apart fails and is named, a phi_J shift of
// 0.01 fails its own verdict, large errors and fits of quality poor are inconclusive, and
// without per-size fits it says so (a design of fewer than 3 rates as such). The t quantiles are
// checked against tabulated values.
#include <gsl/gsl_cdf.h>

#include <boost/test/unit_test.hpp>

#include "checks/checks.hpp"

using namespace jam::checks;

namespace {

FamilyParameters family(std::int64_t n, double beta, double y, double phi_j, double error) {
  FamilyParameters f;
  f.n = n;
  f.phi_init = 0.4;
  f.beta = beta, f.beta_err = error * beta;
  f.y = y, f.y_err = error * y;
  f.phi_j = phi_j, f.phi_j_err = error * 0.01;  // 0.0001 at 1%, 0.002 at 20%
  f.samples = 10;
  return f;
}

std::vector<Verdict> judged(FamilyParameters a, FamilyParameters b) {
  StatsData d;
  d.families = {a, b};
  return fit_parameters_check(d, CheckOptions{});
}

}  // namespace

BOOST_AUTO_TEST_CASE(student_t_quantiles) {
  // Tables: t_{0.975, 9} = 2.262, t_{0.95, 9} = 1.833.
  BOOST_TEST(gsl_cdf_tdist_Qinv(0.025, 9) == 2.262, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(gsl_cdf_tdist_Qinv(0.05, 9) == 1.833, boost::test_tools::tolerance(1e-3));
}

BOOST_AUTO_TEST_CASE(equal_parameters_pass_and_different_ones_fail) {
  // 1% errors: beta and y equal pass at 10%; the verdicts name sizes and the parameters.
  const auto same =
      judged(family(256, 2.8, 1.05, 0.8415, 0.01), family(1024, 2.8, 1.05, 0.8415, 0.01));
  BOOST_TEST_REQUIRE(same.size() == 2u);
  for (const auto& v : same) BOOST_TEST(v.status == "pass", v.check << ": " << v.reason);
  BOOST_TEST(same[0].case_name == "exponents, n256 vs n1024, phi_init 0.4");
  BOOST_TEST(same[1].check == "fit_phi_j");
  // beta 30% apart: fails, and the reason says beta differs (y does not).
  const auto beta =
      judged(family(256, 3.8, 1.05, 0.8415, 0.01), family(1024, 2.8, 1.05, 0.8415, 0.01));
  BOOST_TEST(beta[0].status == "fail", beta[0].reason);
  BOOST_TEST(beta[0].reason.find("differ: beta") != std::string::npos, beta[0].reason);
  BOOST_TEST(beta[1].status == "pass", beta[1].reason);
  // phi_J 0.01 apart (margin 0.002): its own verdict fails.
  const auto phi =
      judged(family(256, 2.8, 1.05, 0.8515, 0.01), family(1024, 2.8, 1.05, 0.8415, 0.01));
  BOOST_TEST(phi[1].status == "fail", phi[1].reason);
  BOOST_TEST(phi[0].status == "pass", phi[0].reason);
}

BOOST_AUTO_TEST_CASE(large_errors_are_inconclusive) {
  // 20% errors: nothing detected, 10% not excluded.
  const auto v = judged(family(256, 2.9, 1.05, 0.8415, 0.2), family(1024, 2.8, 1.05, 0.8415, 0.2));
  BOOST_TEST(v[0].status == "inconclusive", v[0].reason);
  BOOST_TEST(v[1].status == "inconclusive", v[1].reason);
}

// A fit of quality poor compares nothing: beta 30% apart with 1% errors fails between two fits
// of quality ok, and is inconclusive, naming the poor fit and its reason, when one is poor
// (paper-2d's N = 16384 at rate_max 1e-7: chi^2/dof 7.5, beta 3.75 against 2.11).
BOOST_AUTO_TEST_CASE(a_poor_fit_is_not_compared) {
  FamilyParameters poor = family(256, 3.8, 1.05, 0.8415, 0.01);
  poor.quality = "poor";
  poor.quality_reason = "chi^2/dof 7.48 above 3: the scaling form does not describe these points";
  const auto v = judged(poor, family(1024, 2.8, 1.05, 0.8415, 0.01));
  BOOST_TEST_REQUIRE(v.size() == 2u);
  for (const auto& x : v) {
    BOOST_TEST(x.status == "inconclusive", x.reason);
    BOOST_TEST(
        x.reason.find("n256 phi_init 0.4 is of quality poor (chi^2/dof 7.48") != std::string::npos,
        x.reason);
  }
}

BOOST_AUTO_TEST_CASE(without_family_fits_it_says_so) {
  const auto v = fit_parameters_check(StatsData{}, CheckOptions{});
  BOOST_TEST_REQUIRE(v.size() == 2u);
  BOOST_TEST(v[0].status == "inconclusive");
  BOOST_TEST(v[1].check == "fit_phi_j");
  BOOST_TEST(v[0].reason.find("fit/families") != std::string::npos, v[0].reason);
  FamilyParameters broken = family(256, 2.8, 1.05, 0.8415, 0.01);
  broken.failure = "fit: 0 points in the window";
  const auto w = judged(broken, family(1024, 2.8, 1.05, 0.8415, 0.01));
  BOOST_TEST(w[0].status == "inconclusive");
  BOOST_TEST(w[0].reason.find("0 points in the window") != std::string::npos, w[0].reason);
}

// A design of fewer than 3 rates has no scaling fit (`jam stats` attempts none): said as
// such, naming the rates, not as fits missing from stats.h5.
BOOST_AUTO_TEST_CASE(a_design_of_fewer_than_three_rates_says_so) {
  StatsData d;
  for (double rate : {-2.5, -3.0}) {
    EnsembleTables e;
    e.n = 256;
    e.log10_rate = rate;
    d.ensembles.push_back(e);
  }
  const auto two = fit_parameters_check(d, CheckOptions{});
  BOOST_TEST_REQUIRE(two.size() == 2u);
  for (const auto& v : two) {
    BOOST_TEST(v.status == "inconclusive");
    BOOST_TEST(v.reason.find("no scaling fit: fewer than 3 rates (the campaign has 2: 1e-2.5, "
                             "1e-3)") == 0u,
               v.reason);
    BOOST_TEST(short_reason(v) == "no scaling fit", v.reason);
  }
  // Three rates and still no per-size fits: the file is what is missing.
  d.ensembles.push_back(d.ensembles.back());
  d.ensembles.back().log10_rate = -3.5;
  const auto three = fit_parameters_check(d, CheckOptions{});
  BOOST_TEST(three[0].reason.find("fit/families") != std::string::npos, three[0].reason);
}
