// The critical scaling fit on synthetic data drawn from a known scaling function, with
// sample-to-sample noise that is correlated along each run: it recovers phi_J, beta and y
// within their errors, about 68% of its 1-sigma intervals cover the truth (measured over many
// data sets), and impossible fits fail with a message.
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "stats/scaling_fit.hpp"
#include "synthetic_scaling.hpp"

using namespace jam::stats;

using jam::test::synthetic;
using jam::test::Truth;

namespace {


ScalingFitOptions cubic_options() {
  ScalingFitOptions o;
  o.order = 3;
  o.half_window = 0.04;
  o.rate_max = 1e-5;
  return o;  // no start: it comes from the data
}

}  // namespace

BOOST_AUTO_TEST_CASE(recovers_the_truth_within_errors) {
  const Truth t;
  const ScalingFitResult r = fit_scaling(synthetic(t, 1), cubic_options());
  BOOST_TEST_MESSAGE("phi_J " << r.phi_j << " +- " << r.phi_j_err << ", beta " << r.beta << " +- "
                              << r.beta_err << ", y " << r.y << " +- " << r.y_err << ", chi2/dof "
                              << r.chi2_diag_per_dof << " (diag) " << r.chi2_cov_per_dof
                              << " (cov), cond " << r.condition_number << ", points " << r.points);
  // Three standard errors: a single data set misses by more than that 0.3% of the time.
  BOOST_TEST(std::abs(r.phi_j - t.phi_j) < 3 * r.phi_j_err);
  BOOST_TEST(std::abs(r.beta - t.beta()) < 3 * r.beta_err);
  BOOST_TEST(std::abs(r.y - t.y()) < 3 * r.y_err);
  BOOST_TEST(r.phi_j_err < 0.006);  // and informative: the window is +-0.04 wide
  // The window is centred on the fitted phi_J (the plain fit's), after at least one iteration.
  BOOST_TEST(0.5 * (r.phi_min + r.phi_max) == r.phi_j_plain, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(r.iterations >= 1);
  BOOST_TEST(r.start.find("from the data") != std::string::npos, r.start);
  BOOST_TEST(r.quality == "ok", r.quality_reason);
  BOOST_TEST(r.samples == 10u);
  BOOST_TEST(r.fixed.empty());
  BOOST_TEST(r.condition_number > 1.0);
  // Every point of the window satisfies |x| <= 1 at the fitted parameters.
  for (const auto& p : r.collapse) {
    if (p.in_fit) BOOST_TEST(std::abs(p.x) <= 1.0 + 1e-9);
  }
}

BOOST_AUTO_TEST_CASE(one_sigma_intervals_cover_the_truth_about_68_percent) {
  const Truth t;
  const int sets = 120;
  int phi_hits = 0, beta_hits = 0, y_hits = 0;
  for (int k = 0; k < sets; ++k) {
    const ScalingFitResult r = fit_scaling(synthetic(t, 100 + k), cubic_options());
    phi_hits += std::abs(r.phi_j - t.phi_j) <= r.phi_j_err;
    beta_hits += std::abs(r.beta - t.beta()) <= r.beta_err;
    y_hits += std::abs(r.y - t.y()) <= r.y_err;
  }
  const double f_phi = double(phi_hits) / sets, f_beta = double(beta_hits) / sets,
               f_y = double(y_hits) / sets;
  BOOST_TEST_MESSAGE("coverage of 1-sigma intervals: phi_J " << f_phi << ", beta " << f_beta
                                                             << ", y " << f_y);
  // Nominal 0.68 (0.656 for a t distribution with 9 degrees of freedom, the 10 samples);
  // with 120 sets the binomial standard deviation is 0.043: accept 0.52 .. 0.82.
  for (double f : {f_phi, f_beta, f_y}) {
    BOOST_TEST(f > 0.52);
    BOOST_TEST(f < 0.82);
  }
}

BOOST_AUTO_TEST_CASE(fixed_exponents_are_reported_and_held) {
  const Truth t;
  ScalingFitOptions o = cubic_options();
  o.fixed_rate_exponent = t.rate_exponent;
  o.fixed_inv_znu = t.inv_znu;
  const ScalingFitResult r = fit_scaling(synthetic(t, 2), o);
  BOOST_TEST(r.fixed == "q, 1/(z nu)");
  BOOST_TEST(r.rate_exponent == t.rate_exponent);
  BOOST_TEST(r.inv_znu == t.inv_znu);
  BOOST_TEST(r.rate_exponent_err == 0.0);
  BOOST_TEST(std::abs(r.phi_j - t.phi_j) < 3 * r.phi_j_err);
  BOOST_TEST(r.free_parameters == 5u);  // phi_J and c_0 .. c_3
}

BOOST_AUTO_TEST_CASE(chi2_with_the_sample_covariance_is_near_one_on_the_true_model) {
  // Neighbouring points share their noise, so the diagonal chi^2 says little; with the
  // (shrunk) sample covariance chi^2/dof of the true model is near 1. Measured over five data
  // sets of 40 samples: each within 0.6 .. 1.5.
  const Truth t;
  for (std::uint64_t seed = 10; seed < 15; ++seed) {
    const ScalingFitResult r = fit_scaling(synthetic(t, seed, 40), cubic_options());
    BOOST_TEST_MESSAGE("chi2/dof: diagonal " << r.chi2_diag_per_dof << ", covariance "
                                             << r.chi2_cov_per_dof << " (lambda " << r.shrinkage
                                             << ")");
    BOOST_TEST(r.chi2_cov_per_dof > 0.6);
    BOOST_TEST(r.chi2_cov_per_dof < 1.5);
  }
}

// Planted truths away from the paper's values, 2D-like and 3D-like: phi_J, q and 1/(z nu)
// recovered within three standard errors, with the window centred on the recovered phi_J.
BOOST_AUTO_TEST_CASE(planted_truths_away_from_the_paper_are_recovered) {
  Truth two;
  two.phi_j = 0.826;
  two.rate_exponent = 0.35;
  two.inv_znu = 0.32;
  Truth three;  // 3D-like, on packings 0.60 .. 0.72
  three.phi_j = 0.660;
  three.rate_exponent = 0.25;
  three.inv_znu = 0.22;
  for (const Truth* t : {&two, &three}) {
    const auto data = t == &three ? synthetic(*t, 21, 10, 0.60, 0.72) : synthetic(*t, 21);
    const ScalingFitResult r = fit_scaling(data, cubic_options());
    BOOST_TEST_MESSAGE("planted phi_J " << t->phi_j << ": " << r.phi_j << " +- " << r.phi_j_err
                                        << ", q " << r.rate_exponent << " +- "
                                        << r.rate_exponent_err << ", 1/(z nu) " << r.inv_znu
                                        << " +- " << r.inv_znu_err << ", " << r.iterations
                                        << " iterations; " << r.start);
    BOOST_TEST(std::abs(r.phi_j - t->phi_j) < 3 * r.phi_j_err);
    BOOST_TEST(std::abs(r.rate_exponent - t->rate_exponent) < 3 * r.rate_exponent_err);
    BOOST_TEST(std::abs(r.inv_znu - t->inv_znu) < 3 * r.inv_znu_err);
    BOOST_TEST(0.5 * (r.phi_min + r.phi_max) == r.phi_j_plain, boost::test_tools::tolerance(1e-12));
  }
}

BOOST_AUTO_TEST_CASE(impossible_fits_fail_with_a_message) {
  const Truth t;
  ScalingFitOptions o = cubic_options();
  o.rate_max = 1e-7;  // below every rate
  BOOST_CHECK_EXCEPTION(fit_scaling(synthetic(t, 4), o), FitError, [](const FitError& e) {
    return std::string(e.what()).find("0 rate(s) at or below rate_max") != std::string::npos;
  });
  o = cubic_options();
  o.half_window = 0.0005;
  BOOST_CHECK_EXCEPTION(fit_scaling(synthetic(t, 4), o), FitError, [](const FitError& e) {
    return std::string(e.what()).find("free parameters") != std::string::npos;
  });
  // The window cannot settle in one re-centring at a tolerance no fit meets.
  o = cubic_options();
  o.max_iterations = 1;
  o.tolerance = 1e-300;
  BOOST_CHECK_EXCEPTION(fit_scaling(synthetic(t, 4), o), FitError, [](const FitError& e) {
    return std::string(e.what()).find("did not settle") != std::string::npos;
  });
}

// A pressure that does not depend on the rate at all (q = 0) drives q onto its bound: a
// failure naming it, not a result. Data without a crossover give no start.
BOOST_AUTO_TEST_CASE(a_fit_on_a_bound_or_without_a_start_is_no_result) {
  Truth flat;
  flat.rate_exponent = 0.0;
  flat.inv_znu = 0.3;
  ScalingFitOptions o = cubic_options();
  o.fixed_phi_j = flat.phi_j;  // the start needs a crossover, which q = 0 has not
  BOOST_CHECK_EXCEPTION(fit_scaling(synthetic(flat, 5), o), FitError, [](const FitError& e) {
    return std::string(e.what()).find("ends on a bound: q") != std::string::npos;
  });
  // p proportional to the rate at every packing (q_eff = 1 throughout): no crossover.
  auto viscous = synthetic(Truth{}, 5);
  for (auto& e : viscous)
    for (auto& row : e.pressure)
      for (std::size_t k = 0; k < row.size(); ++k) row[k] = e.rate * std::exp(10 * e.phi[k]);
  BOOST_CHECK_EXCEPTION(fit_scaling(viscous, cubic_options()), FitError, [](const FitError& e) {
    return std::string(e.what()).find("no start from the data") != std::string::npos;
  });
}

// Too few points of a rate in the window: a result, flagged poor with the reason.
BOOST_AUTO_TEST_CASE(too_few_points_per_rate_is_flagged) {
  const Truth t;
  auto data = synthetic(t, 6);
  // The slowest rate keeps one packing in 25: about 3 in the window.
  FitEnsemble& slow = data.back();
  FitEnsemble sparse = slow;
  sparse.phi.clear();
  for (auto& row : sparse.pressure) row.clear();
  for (std::size_t k = 0; k < slow.phi.size(); k += 25) {
    sparse.phi.push_back(slow.phi[k]);
    for (std::size_t s = 0; s < slow.pressure.size(); ++s)
      sparse.pressure[s].push_back(slow.pressure[s][k]);
  }
  slow = sparse;
  const ScalingFitResult r = fit_scaling(data, cubic_options());
  BOOST_TEST(r.min_points_per_rate < kMinPointsPerRate);
  BOOST_TEST(r.quality == "poor");
  BOOST_TEST(r.quality_reason.find("points in the window") != std::string::npos, r.quality_reason);
}

// Data the form does not describe: the slowest rate's pressure 15% higher everywhere (no single
// power of the rate follows it), 1% scatter so that the misfit dominates. The fit returns,
// flagged poor for its chi^2/dof; the same data without it stay ok.
BOOST_AUTO_TEST_CASE(a_fit_far_above_chi2_one_is_flagged_poor) {
  const Truth t;
  auto clean = synthetic(t, 8, 10);
  for (auto& e : clean)
    for (std::size_t s = 0; s < e.pressure.size(); ++s)
      for (std::size_t k = 0; k < e.phi.size(); ++k)
        e.pressure[s][k] = t.pressure(e.phi[k], e.rate) * (1 + 0.01 * std::sin(7.0 * s + k));
  auto kinked = clean;
  FitEnsemble& slow = kinked.back();
  for (auto& row : slow.pressure)
    for (double& p : row) p *= 1.15;
  const ScalingFitResult good = fit_scaling(clean, cubic_options());
  BOOST_TEST(good.quality_reason.find("does not describe") == std::string::npos,
             good.quality_reason);
  const ScalingFitResult bad = fit_scaling(kinked, cubic_options());
  BOOST_TEST_MESSAGE("chi^2/dof clean " << good.chi2_cov_per_dof << ", kinked "
                                        << bad.chi2_cov_per_dof);
  BOOST_TEST(bad.quality == "poor");
  BOOST_TEST(bad.quality_reason.find("does not describe") != std::string::npos, bad.quality_reason);
}

// A fit whose exponents' errors exceed half their values agrees with anything: flagged poor
// ("uninformative"), so that it can neither be the scan's representative nor make a drifting
// scan look flat. Four samples at 30% scatter over three rates (beta 0.57 +- 0.89); ten at 3%
// scatter are informative.
BOOST_AUTO_TEST_CASE(an_uninformative_fit_is_flagged_poor) {
  const Truth t;
  ScalingFitOptions o = cubic_options();
  o.rate_max = std::pow(10.0, -5.5);  // three rates
  const ScalingFitResult noisy = fit_scaling(synthetic(t, 3, 4, 0.78, 0.90, 0.3), o);
  BOOST_TEST_MESSAGE("noisy: beta " << noisy.beta << " +- " << noisy.beta_err << ", y " << noisy.y
                                    << " +- " << noisy.y_err << "; " << noisy.quality_reason);
  BOOST_TEST(noisy.quality == "poor");
  BOOST_TEST(noisy.quality_reason.find("uninformative") != std::string::npos,
             noisy.quality_reason);
  const ScalingFitResult clean = fit_scaling(synthetic(t, 3, 10, 0.78, 0.90, 0.03), o);
  BOOST_TEST(clean.quality_reason.find("uninformative") == std::string::npos,
             clean.quality_reason);
}
