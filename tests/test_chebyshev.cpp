// The Runge-Kutta-Chebyshev integrator (sim/dynamics/overdamped_chebyshev.hpp): its
// coefficients (stage times end at 1, the stability interval grows as ~0.65 s^2), the
// stability interval on a harmonic chain whose eigenvalues are known in closed form, second
// order measured on two relaxing particles, and the error controller rejecting a step across a
// planted stiff event and still landing on the reference.
#define BOOST_TEST_MODULE chebyshev
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/dynamics/overdamped_chebyshev.hpp"
#include "sim/dynamics/overdamped_heun.hpp"

using namespace jam;

BOOST_AUTO_TEST_CASE(coefficients) {
  for (int s : {2, 3, 5, 10, 40, 150, kMaxChebyshevStages}) {
    const ChebyshevCoefficients k = chebyshev_coefficients(s);
    // The scheme applied to y' = 1 reaches t + h: c_s = 1 (round-off of the recursion).
    BOOST_TEST(k.c[s] == 1.0, boost::test_tools::tolerance(1e-10));
    // beta(s) against the asymptotic law (2/3)(s^2 - 1)(1 - 2 eps / 15) of Verwer et al.:
    // within 2.5% for even s (2.1% at s = 2, where beta = 2 exactly) (the law drops terms of
    // relative order 1/s^2 and eps^2); odd s reach further (to 18% at s = 3, less as s grows).
    const double law = (2.0 / 3.0) * (s * s - 1.0) * (1.0 - (2.0 / 15.0) * kChebyshevDamping);
    if (s % 2 == 0) BOOST_TEST(k.beta == law, boost::test_tools::tolerance(0.025));
    BOOST_TEST(k.beta >= 0.98 * law);
    BOOST_TEST(k.beta <= 1.2 * law);
  }
  // The fewest stages that hold h rho.
  for (double h_rho : {0.5, 3.0, 50.0, 2000.0}) {
    const int s = chebyshev_stages(h_rho);
    BOOST_TEST(chebyshev_stability_interval(s) >= 1.05 * h_rho);
    if (s > 2) BOOST_TEST(chebyshev_stability_interval(s - 1) < 1.05 * h_rho);
  }
}

namespace {

// A periodic chain of m small particles along x at spacing a < 1 (every neighbour pair in
// contact), the box m a long: the longitudinal modes of the harmonic chain have rates
// lambda_q = (2 / gamma_s)(1 - cos q) U'' with U'' = 1 and gamma_s = 1 in 2D, the largest
// (q = pi, alternating displacements) lambda_max = 4. Returns the largest growth of that mode's
// amplitude over `steps` RKC steps of size h with s stages (the largest: a mode that blows up
// ends the contacts, and the chain can fall back to even spacing afterwards).
double growth_of_stiffest_mode(int s, double h, int steps) {
  const int m = 16;
  const double a = 0.9, L = m * a, amplitude = 1e-4;
  std::vector<std::array<double, 2>> r;
  std::vector<int> type;
  for (int i = 0; i < m; ++i) {
    r.push_back({-0.5 * L + (i + 0.5) * a + (i % 2 ? amplitude : -amplitude), 0.0});
    type.push_back(0);
  }
  auto sys = test::make_system<2>(r, type, L, 0.0, 0.3);
  BOOST_TEST_REQUIRE(sys.box.length(0.0) > 2.0 * (1.0 + 0.3));  // minimum image holds
  sys.guard_rebuilds = false;  // outside the interval the chain is meant to blow up
  OverdampedChebyshev<2> stepper(sys.size(), 1.0, h);
  double largest = 0.0;
  for (int k = 0; k < steps; ++k) {
    stepper.fixed_step(sys, k * h, h, s);
    const auto dr = test::separation(sys, 1, 0, L);
    largest = std::max(largest, std::abs(std::abs(dr[0]) - a) / (2.0 * amplitude));
  }
  return largest;
}

}  // namespace

BOOST_AUTO_TEST_CASE(stability_interval_on_a_harmonic_chain) {
  const double lambda_max = 4.0;
  for (int s : {3, 6, 12, 25, 40}) {
    BOOST_TEST_CONTEXT("s = " << s) {
      const double beta = chebyshev_stability_interval(s);
      // Inside the interval the stiffest mode decays (|R| < 1, damped); 10% beyond it grows.
      const double inside = growth_of_stiffest_mode(s, 0.9 * beta / lambda_max, 30);
      const double outside = growth_of_stiffest_mode(s, 1.1 * beta / lambda_max, 30);
      BOOST_TEST_MESSAGE("growth over 30 steps: " << inside << " inside, " << outside
                                                  << " outside");
      BOOST_TEST(inside < 1.0);  // every step's amplification below 1
      BOOST_TEST(outside > 10.0);
    }
  }
}

namespace {

// Two small particles at r0 = 0.8 relax as delta(t) = delta0 exp(-2 t) in 2D (gamma_s = 1,
// d = 1; test_two_particle_relaxation derives it).
double relaxation_error(int s, double h) {
  const double L = 10.0, r0 = 0.8, t_end = 1.0;
  auto sys = test::make_system<2>({{-0.5 * r0, 0.0}, {0.5 * r0, 0.0}}, {0, 0}, L);
  OverdampedChebyshev<2> stepper(sys.size(), 1.0, h);
  const auto steps = static_cast<long>(std::llround(t_end / h));
  for (long k = 0; k < steps; ++k) stepper.fixed_step(sys, k * h, h, s);
  const double exact = 1.0 - (1.0 - r0) * std::exp(-2.0 * t_end);
  return std::abs(-test::separation(sys, 0, 1, L)[0] - exact);
}

}  // namespace

BOOST_AUTO_TEST_CASE(second_order) {
  for (int s : {2, 4, 8}) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const int m = 5;
    for (int k = 0; k < m; ++k) {
      const double h = 0.1 / std::pow(2.0, k);
      const double x = std::log(h), y = std::log(relaxation_error(s, h));
      sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double order = (m * sxy - sx * sy) / (m * sxx - sx * sx);
    BOOST_TEST_MESSAGE(s << " stages: measured order " << order);
    BOOST_TEST(std::abs(order - 2.0) < 0.1);
  }
}

BOOST_AUTO_TEST_CASE(controller_rejects_a_step_across_a_stiff_event) {
  // A dilute random packing (few contacts, calm) with one pair planted deep in overlap: a
  // first step of 50 t0 tried there carries a local error far above the tolerance, so it is
  // rejected and retried shorter; the result still follows a fine Heun reference.
  auto reference = test::random_system<2>(64, 0.3, 5);
  for (int d = 0; d < 2; ++d)
    reference.particles.s[d][1] = wrap_unit(reference.particles.s[d][0] + 0.01);
  auto sys = reference;
  const double t_end = 60.0, tolerance = 1e-6;
  OverdampedChebyshev<2> stepper(sys.size(), tolerance, 50.0);
  for (double t = 0.0; t < t_end;) {
    const double h = stepper.step(sys, t, t_end - t);
    t = h == t_end - t ? t_end : t + h;
  }
  BOOST_TEST(stepper.stats().rejections >= 1u);
  OverdampedHeun<2> heun(reference.size());
  const double dt = 1e-3;
  for (long k = 0; k < std::lround(t_end / dt); ++k) heun.step(reference, k * dt, dt);
  const double L = sys.box.length(0.0);
  double worst = 0.0;
  for (int d = 0; d < 2; ++d)
    for (std::size_t i = 0; i < sys.size(); ++i)
      worst = std::max(
          worst, L * std::abs(minimum_image(sys.particles.s[d][i] - reference.particles.s[d][i])));
  BOOST_TEST_MESSAGE("largest difference from Heun at dt 1e-3: "
                     << worst << " after " << stepper.stats().attempts << " attempts");
  // Local errors of 1e-6 per step over a few hundred steps, all decaying (the relaxation
  // contracts): well below 1e-4, while a step that skipped the event would be off by ~0.1.
  BOOST_TEST(worst < 1e-4);
}
