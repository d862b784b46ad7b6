// Without contacts, particles follow the host flow exactly: r(t) = (L(t)/L0) r(0), and the
// packing follows phi(t) = phi_init exp(D rate t). Every integrator of the list
// (sim/dynamics/integrators.hpp).
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/dynamics/integrators.hpp"

using namespace jam;

namespace {

// A dilute simple lattice (spacing 3, far beyond contact) compressed for 2000 steps at
// rate 1e-3 (the box shrinks by 2%, still no contact).
template <int D, class Stepper>
void check_affine() {
  const int m = 4;
  const double spacing = 3.0, L = m * spacing, rate = 1e-3, dt = 0.01;
  std::vector<std::array<double, D>> r;
  std::vector<int> type;
  for (int k = 0; k < static_cast<int>(std::pow(m, D)); ++k) {
    std::array<double, D> x;
    int rest = k;
    for (int d = 0; d < D; ++d) {
      x[d] = (rest % m + 0.25 + 0.1 * d) * spacing - 0.5 * L;
      rest /= m;
    }
    r.push_back(x);
    type.push_back(k % 2);
  }
  System<D> sys = test::make_system<D>(r, type, L, rate);
  const double phi0 = sys.box.packing_fraction(0.0);
  // Q = 0.1 for the inertial integrator; the adaptive one starts at dt and may lengthen it.
  Stepper stepper(sys.size(), StepperOptions{0.1, 1e-6, dt});
  const int steps = 2000;
  if constexpr (is_adaptive<Stepper>()) {
    for (double now = 0.0; now < steps * dt;) {
      const double h = stepper.step(sys, now, steps * dt - now);
      now = h == steps * dt - now ? steps * dt : now + h;
    }
  } else {
    for (int k = 0; k < steps; ++k) stepper.step(sys, k * dt, dt);
  }
  const double t = steps * dt;
  const double Lt = sys.box.length(t);
  // Positions: the non-affine displacement must be exactly zero (no force acts), so the
  // physical position is the affine image of the start to round-off of one multiplication.
  for (std::size_t i = 0; i < sys.size(); ++i) {
    for (int d = 0; d < D; ++d) {
      const double now = Lt * (sys.particles.s[d][i] - 0.5);
      const double affine = (Lt / L) * r[i][d];
      BOOST_TEST(std::abs(now - affine) <= 1e-13 * L);
    }
  }
  // Packing against the closed form; both sides are one exp() of the same argument apart.
  BOOST_TEST(sys.box.packing_fraction(t) == phi0 * std::exp(D * rate * t),
             boost::test_tools::tolerance(1e-14));
  BOOST_TEST(Lt == L * std::exp(-rate * t), boost::test_tools::tolerance(1e-15));
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(affine_2d, Stepper, Integrators<2>) {
  check_affine<2, Stepper>();
}

BOOST_AUTO_TEST_CASE_TEMPLATE(affine_3d, Stepper, Integrators<3>) {
  check_affine<3, Stepper>();
}

BOOST_AUTO_TEST_CASE(box_never_accumulates) {
  // L(t) is computed from t at every step: after 1e7 steps of dt = 0.01 at rate 1e-8.5 the
  // packing is the closed form to round-off of exp().
  CompressingBox<2> box{50.0, std::pow(10.0, -8.5), 0.84 * 2500.0};
  const double t = 1e7 * 0.01;
  BOOST_TEST(box.packing_fraction(t) == 0.84 * std::exp(2 * std::pow(10.0, -8.5) * t),
             boost::test_tools::tolerance(1e-15));
  BOOST_TEST(box.time_at_packing(box.packing_fraction(t)) == t,
             boost::test_tools::tolerance(1e-12));
}
