// Two overlapping particles relax as the closed-form solution of the overdamped equation of
// motion, and the integrators converge at their order in dt (measured slopes).
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"

using namespace jam;

namespace {

// With r = |r_1 - r_2| < d and delta = 1 - r/d, the equation of motion
// dr_i/dt = f_i / gamma_i with |f| = delta / d gives d(delta)/dt = -(1/g1 + 1/g2) delta / d^2,
// so delta(t) = delta0 exp(-(1/g1 + 1/g2) t / d^2).
template <int D>
double exact_separation(double r0, double d, double g1, double g2, double t) {
  const double delta0 = 1.0 - r0 / d;
  return d * (1.0 - delta0 * std::exp(-(1.0 / g1 + 1.0 / g2) * t / (d * d)));
}

// gamma_i = k_d V_i with k_d V_s = 2/D (t0 = 1), V_b / V_s = 1.4^D: the paper's definitions,
// written out independently of sim/model/species.hpp.
template <int D>
double paper_drag(int type) {
  return (2.0 / D) * (type == 0 ? 1.0 : std::pow(1.4, D));
}

template <int D>
double paper_contact_distance(int t1, int t2) {
  return 0.5 * ((t1 == 0 ? 1.0 : 1.4) + (t2 == 0 ? 1.0 : 1.4));
}

template <int D, class Stepper>
double separation_after(double r0, int type1, int type2, double t_end, double dt) {
  const double L = 10.0;
  std::array<double, D> a{}, b{};
  a[0] = -0.5 * r0;
  b[0] = 0.5 * r0;
  if constexpr (D == 3) a[2] = b[2] = 0.3;  // off any symmetry plane of the cell grid
  System<D> sys = test::make_system<D>({a, b}, {type1, type2}, L);
  Stepper stepper(sys.size());
  const auto steps = static_cast<long>(std::llround(t_end / dt));
  for (long k = 0; k < steps; ++k) stepper.step(sys, static_cast<double>(k) * dt, dt);
  const auto dr = test::separation(sys, 1, 0, L);
  double r2 = 0.0;
  for (double x : dr) r2 += x * x;
  return std::sqrt(r2);
}

// Slope of log(error) against log(dt) by least squares over halving dt.
template <int D, class Stepper>
double convergence_order(int type1, int type2) {
  const double d = paper_contact_distance<D>(type1, type2);
  const double r0 = 0.8 * d, t_end = 1.0;
  const double exact =
      exact_separation<D>(r0, d, paper_drag<D>(type1), paper_drag<D>(type2), t_end);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const int m = 5;
  for (int k = 0; k < m; ++k) {
    const double dt = 0.1 / std::pow(2.0, k);
    const double err = std::abs(separation_after<D, Stepper>(r0, type1, type2, t_end, dt) - exact);
    const double x = std::log(dt), y = std::log(err);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

}  // namespace

BOOST_AUTO_TEST_CASE(heun_matches_closed_form_at_small_dt) {
  // Heun's global error is O(dt^2) with a constant of order rate^3 delta0 t ~ 1: dt = 1e-3
  // leaves about 1e-7 on a separation of 1, so 1e-6 is a safe bound.
  for (auto [t1, t2] : {std::pair{0, 0}, std::pair{0, 1}, std::pair{1, 1}}) {
    const double d2 = paper_contact_distance<2>(t1, t2);
    const double got2 = separation_after<2, OverdampedHeun<2>>(0.8 * d2, t1, t2, 1.0, 1e-3);
    const double want2 =
        exact_separation<2>(0.8 * d2, d2, paper_drag<2>(t1), paper_drag<2>(t2), 1.0);
    BOOST_TEST(got2 == want2, boost::test_tools::tolerance(1e-6));
    const double d3 = paper_contact_distance<3>(t1, t2);
    const double got3 = separation_after<3, OverdampedHeun<3>>(0.8 * d3, t1, t2, 1.0, 1e-3);
    const double want3 =
        exact_separation<3>(0.8 * d3, d3, paper_drag<3>(t1), paper_drag<3>(t2), 1.0);
    BOOST_TEST(got3 == want3, boost::test_tools::tolerance(1e-6));
  }
}

BOOST_AUTO_TEST_CASE(euler_converges_at_first_order) {
  // Measured slopes; asymptotic order 1 within 0.1 over dt = 0.1 ... 0.00625.
  BOOST_TEST(std::abs(convergence_order<2, OverdampedEuler<2>>(0, 1) - 1.0) < 0.1);
  BOOST_TEST(std::abs(convergence_order<3, OverdampedEuler<3>>(1, 1) - 1.0) < 0.1);
}

BOOST_AUTO_TEST_CASE(heun_converges_at_second_order) {
  BOOST_TEST(std::abs(convergence_order<2, OverdampedHeun<2>>(0, 1) - 2.0) < 0.1);
  BOOST_TEST(std::abs(convergence_order<3, OverdampedHeun<3>>(1, 1) - 2.0) < 0.1);
}
