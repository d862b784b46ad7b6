// The virial pressure (trace of the paper's stress tensor over D) equals -dE/dV, and the
// elastic forces equal -grad E, both from central finite differences of the total energy,
// on random overlapping configurations in 2D and 3D, for every contact law.
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/observables/observables.hpp"

using namespace jam;

namespace {

template <int D, class Contact>
double total_energy(System<D, Contact>& sys, double L) {
  // Energy at box length L with the same scaled positions: an affine change of the box.
  CompressingBox<D> saved = sys.box;
  sys.box.initial_length = L;
  const double e = measure(sys, 0.0, false).energy_per_particle * sys.size();
  sys.box = saved;
  return e;
}

template <int D, class Contact>
void check_pressure(double phi, std::uint64_t seed) {
  auto sys = test::random_system<D, Contact>(200, phi, seed);
  const double L = sys.box.length(0.0);
  const auto obs = measure(sys, 0.0, false);
  BOOST_TEST_REQUIRE(obs.contacts_per_particle > 2.0);  // genuinely overlapping
  // Central difference, h = 1e-6 L: truncation O(h^2) is ~1e-12 relative where E is smooth;
  // pairs crossing contact within +-h make E only C^1 there, an O(h) ~ 1e-6 effect at most.
  const double h = 1e-6 * L;
  const double dE_dL = (total_energy(sys, L + h) - total_energy(sys, L - h)) / (2.0 * h);
  const double p_fd = -dE_dL / (D * std::pow(L, D - 1));
  BOOST_TEST(obs.pressure == p_fd, boost::test_tools::tolerance(1e-6));
  // The stress tensor is symmetric and its trace over D is the pressure.
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      BOOST_TEST(obs.stress[a][b] == obs.stress[b][a], boost::test_tools::tolerance(1e-12));
}

template <int D, class Contact>
void check_forces(double phi, std::uint64_t seed) {
  auto sys = test::random_system<D, Contact>(100, phi, seed);
  const double L = sys.box.length(0.0);
  sys.compute_elastic_forces(L);
  const auto force = sys.force;
  const double h = 1e-7;  // physical displacement
  double max_f = 0.0;
  for (int d = 0; d < D; ++d)
    for (double f : force[d]) max_f = std::max(max_f, std::abs(f));
  for (std::size_t i = 0; i < sys.size(); i += 7) {
    for (int d = 0; d < D; ++d) {
      const double s0 = sys.particles.s[d][i];
      sys.particles.s[d][i] = wrap_unit(s0 + h / L);
      const double ep = total_energy(sys, L);
      sys.particles.s[d][i] = wrap_unit(s0 - h / L);
      const double em = total_energy(sys, L);
      sys.particles.s[d][i] = s0;
      const double f_fd = -(ep - em) / (2.0 * h);
      // Round-off of E (~1e-16 E / h) and the C^1 kink bound the error far below 1e-6 max|f|.
      BOOST_TEST(std::abs(force[d][i] - f_fd) <= 1e-6 * max_f);
    }
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(pressure_is_minus_dE_dV_2d, Contact, ContactLaws) {
  check_pressure<2, Contact>(0.90, 11);
  check_pressure<2, Contact>(0.86, 12);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(pressure_is_minus_dE_dV_3d, Contact, ContactLaws) {
  check_pressure<3, Contact>(0.70, 21);
  check_pressure<3, Contact>(0.66, 22);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(force_is_minus_grad_E, Contact, ContactLaws) {
  check_forces<2, Contact>(0.88, 31);
  check_forces<3, Contact>(0.68, 32);
}
