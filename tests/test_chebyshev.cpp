// The Runge-Kutta-Chebyshev integrator (sim/dynamics/overdamped_chebyshev.hpp): its
// coefficients (stage times end at 1, the stability interval grows as ~0.65 s^2), the
// stability interval on a harmonic chain whose eigenvalues are known in closed form, second
// order measured on two relaxing particles, and the error controller rejecting a step across a
// planted stiff event and still landing on the reference, and the continuous extension (dense
// output) within the step's tolerance of a converged solution from the same start.
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

// The two error norms on the same step: one overlapping pair of small particles along x among
// m - 2 particles that touch nothing. Only the pair moves, symmetrically, so its two particles
// carry equal errors |est| along x and every other entry is zero: the largest component is
// |est|, the root mean square over the m particles sqrt(2 / m) |est|.
BOOST_AUTO_TEST_CASE(error_norms_on_one_pair) {
  const int m = 50;
  std::vector<std::array<double, 2>> r{{{0.0, 0.0}}, {{0.8, 0.0}}};
  std::vector<int> type{0, 0};
  for (int k = 2; k < m; ++k) {
    r.push_back({{3.0 * (k % 7) - 9.5, 3.0 * (k / 7) + 3.0}});
    type.push_back(0);
  }
  auto a = test::make_system<2>(r, type, 60.0);
  auto b = a;
  OverdampedChebyshev<2> largest(a.size(), 1e-4, 0.1), mean(b.size(), 1e-4, 0.1);
  mean.set_error_norm_rms(true);
  const double err_max = largest.fixed_step(a, 0.0, 0.5, 4);
  const double err_rms = mean.fixed_step(b, 0.0, 0.5, 4);
  BOOST_TEST(err_max > 0.0);
  BOOST_TEST(err_rms == std::sqrt(2.0 / m) * err_max, boost::test_tools::tolerance(1e-12));
}

namespace {

// Largest physical distance between the positions of a and b (minimum image).
template <class Positions>
double largest_distance(const Positions& a, const Positions& b, double box_length) {
  double worst = 0.0;
  for (int d = 0; d < 2; ++d)
    for (std::size_t i = 0; i < a[d].size(); ++i)
      worst = std::max(worst, box_length * std::abs(minimum_image(a[d][i] - b[d][i])));
  return worst;
}

}  // namespace

BOOST_AUTO_TEST_CASE(continuous_extension_on_two_relaxing_particles) {
  // delta(t) = delta0 exp(-2 t) (as above). One step of h = 0.2 with 4 stages, then the
  // extension at theta against the exact separation: no further off than the step's end
  // step's own error (which it carries, growing from 0 at theta = 0 to the step's at 1), and
  // exactly the step's ends at theta = 0 and 1 (to round-off).
  const double L = 10.0, r0 = 0.8, h = 0.2;
  auto sys = test::make_system<2>({{-0.5 * r0, 0.0}, {0.5 * r0, 0.0}}, {0, 0}, L);
  const auto start = sys.particles.s;
  OverdampedChebyshev<2> stepper(sys.size(), 1.0, h);
  stepper.fixed_step(sys, 0.0, h, 4);
  BOOST_TEST(stepper.last_step_start() == 0.0);
  BOOST_TEST(stepper.last_step_size() == h);
  std::array<std::vector<double>, 2> between;
  stepper.interpolate(0.0, between);
  BOOST_TEST(largest_distance(between, start, L) < 1e-14);
  stepper.interpolate(h, between);
  BOOST_TEST(largest_distance(between, sys.particles.s, L) < 1e-14);
  const double step_error =
      std::abs(L * minimum_image(sys.particles.s[0][1] - sys.particles.s[0][0]) -
               (1.0 - (1.0 - r0) * std::exp(-2.0 * h)));
  for (double theta : {0.25, 0.5, 0.75}) {
    stepper.interpolate(theta * h, between);
    const double r = L * minimum_image(between[0][1] - between[0][0]);
    const double exact = 1.0 - (1.0 - r0) * std::exp(-2.0 * theta * h);
    // The straight line between the step's ends misses exp's curvature by
    // (1/2) theta (1 - theta) h^2 4 (1 - r0) ~ 3e-3: the extension must do far better.
    const double line = 1.0 - (1.0 - r0) * (1.0 - theta + theta * std::exp(-2.0 * h));
    BOOST_TEST_MESSAGE("theta " << theta << ": extension off by " << std::abs(r - exact)
                                << ", straight line by " << std::abs(line - exact)
                                << ", the step's end by " << step_error);
    BOOST_TEST(std::abs(r - exact) <= step_error);
    BOOST_TEST(std::abs(line - exact) > 2.0 * std::abs(r - exact));
  }
}

BOOST_AUTO_TEST_CASE(continuous_extension_within_the_tolerance) {
  // A random start at phi 0.86, heavily overlapping, compressed at rate 1e-3: the violent
  // relaxation of the start is where the extension has the most to follow. After each accepted
  // step, the extension at theta = 1/3, 1/2, 2/3 against Heun at dt = h/2000 from the same
  // y_n: within the tolerance (the step's own error bound; the extension adds at most 0.37 of
  // it, overdamped_chebyshev.hpp), while the straight line between the ends is not.
  auto sys = test::random_system<2>(256, 0.86, 11, 1e-3);
  const double tolerance = 1e-4;
  OverdampedChebyshev<2> stepper(sys.size(), tolerance, 0.1);
  std::array<std::vector<double>, 2> between;
  double t = 0.0, worst = 0.0, worst_line = 0.0;
  for (int k = 0; k < 12; ++k) {
    const auto before = sys;
    const double h = stepper.step(sys, t, 1e9);
    for (double theta : {1.0 / 3.0, 0.5, 2.0 / 3.0}) {
      auto reference = before;
      OverdampedHeun<2> heun(reference.size());
      const int substeps = 2000;
      const double dt = theta * h / substeps;
      for (int m = 0; m < substeps; ++m) heun.step(reference, t + m * dt, dt);
      stepper.interpolate(t + theta * h, between);
      const double L = sys.box.length(t + theta * h);
      worst = std::max(worst, largest_distance(between, reference.particles.s, L));
      std::array<std::vector<double>, 2> line;
      for (int d = 0; d < 2; ++d) {
        line[d].resize(sys.size());
        for (std::size_t i = 0; i < sys.size(); ++i)
          line[d][i] =
              wrap_unit(before.particles.s[d][i] +
                        theta * minimum_image(sys.particles.s[d][i] - before.particles.s[d][i]));
      }
      worst_line = std::max(worst_line, largest_distance(line, reference.particles.s, L));
    }
    t += h;
  }
  BOOST_TEST_MESSAGE("inside the steps: extension off by at most " << worst << ", straight line by "
                                                                   << worst_line);
  BOOST_TEST(worst < tolerance);
  BOOST_TEST(worst_line > 2.0 * tolerance);  // the comparison resolves a wrong interpolant
}
