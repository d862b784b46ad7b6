// Pressure, Z and energy on hand-built lattices against closed forms. On a simple lattice of
// spacing a, with only nearest neighbours overlapping (d > a, d <= sqrt(2) a):
//   Z = 2D, E/N = D * (1/2) delta^2 with delta = 1 - a/d,
//   p = (1/(D V)) sum_pairs f r = (1/(D a^D N)) * (D N) * (delta/d) * a = delta / (d a^(D-1)).
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/observables/observables.hpp"

using namespace jam;

namespace {

// m^D sites of spacing a; checkerboard alternates small and big when bidisperse.
template <int D>
System<D> simple_lattice(int m, double a, bool bidisperse) {
  std::vector<std::array<double, D>> r;
  std::vector<int> type;
  const double L = m * a;
  const int sites = static_cast<int>(std::pow(m, D));
  for (int k = 0; k < sites; ++k) {
    std::array<double, D> x;
    int rest = k, parity = 0;
    for (int d = 0; d < D; ++d) {
      const int c = rest % m;
      rest /= m;
      parity += c;
      x[d] = (c + 0.5) * a - 0.5 * L;
    }
    r.push_back(x);
    type.push_back(bidisperse ? parity % 2 : 0);
  }
  return test::make_system<D>(r, type, L);
}

template <int D>
void check_lattice(int m, double a, bool bidisperse) {
  System<D> sys = simple_lattice<D>(m, a, bidisperse);
  const double d = bidisperse ? sys.species.contact_distance[1] : 1.0;
  const double delta = 1.0 - a / d;
  const auto obs = measure(sys, 0.0, true);
  // Every quantity is a short exact sum of identical terms: round-off only.
  const auto tol = boost::test_tools::tolerance(1e-12);
  BOOST_TEST(obs.contacts_per_particle == 2.0 * D, tol);
  BOOST_TEST(obs.energy_per_particle == D * 0.5 * delta * delta, tol);
  BOOST_TEST(obs.pressure == delta / (d * std::pow(a, D - 1)), tol);
  // Isotropic: diagonal stress equal to p, off-diagonal zero.
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j)
      BOOST_TEST(std::abs(obs.stress[i][j] - (i == j ? obs.pressure : 0.0)) < 1e-12 * obs.pressure);
  // 2D contacts >= D + 1: nobody is a rattler.
  BOOST_TEST(obs.rattler_fraction == 0.0);
  BOOST_TEST(obs.contacts_per_particle_no_rattlers == 2.0 * D, tol);
}

}  // namespace

BOOST_AUTO_TEST_CASE(square_lattice_2d) {
  check_lattice<2>(8, 0.9, false);
}

BOOST_AUTO_TEST_CASE(checkerboard_bidisperse_2d) {
  // Small-big spacing 1.1 < d_sb = 1.2; same species at 1.1 sqrt(2) = 1.56 > 1.4: no contact.
  check_lattice<2>(8, 1.1, true);
}

BOOST_AUTO_TEST_CASE(simple_cubic_3d) {
  check_lattice<3>(6, 0.9, false);
}

BOOST_AUTO_TEST_CASE(rock_salt_bidisperse_3d) {
  check_lattice<3>(6, 1.1, true);
}

BOOST_AUTO_TEST_CASE(lattice_without_overlap_has_no_pressure) {
  System<2> sys = simple_lattice<2>(8, 1.0 + 1e-12, false);
  const auto obs = measure(sys, 0.0, true);
  BOOST_TEST(obs.pressure == 0.0);
  BOOST_TEST(obs.contacts_per_particle == 0.0);
  BOOST_TEST(obs.rattler_fraction == 1.0);
}
