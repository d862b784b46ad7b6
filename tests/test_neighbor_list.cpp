// The cell-list Verlet list finds exactly the pairs an O(N^2) search finds, and never misses
// a contact between rebuilds while the box shrinks.
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <set>

#include "helpers.hpp"
#include "pair_sets.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/neighbor/brute_force_pairs.hpp"

using namespace jam;
using jam::testing::listed_pairs;
using jam::testing::PairSet;

namespace {

template <int D>
PairSet oracle(const System<D>& sys, double L, double extra) {
  const auto v = brute_force_pairs(sys.particles, sys.species, L, extra);
  return PairSet(v.begin(), v.end());
}

// Compresses a random packing fast (rate 1e-2, large steps so particles move a lot) and
// checks after every step: right after a build the list equals the O(N^2) list at d + skin;
// between builds every contact of the O(N^2) search is in the list.
template <int D>
void compress_and_compare(std::size_t n, double phi, double skin, int steps) {
  System<D> sys = test::random_system<D>(n, phi, 5, 1e-2, skin);
  OverdampedEuler<D> stepper(n);
  const double dt = 0.05;
  std::size_t builds_seen = 0, contacts_checked = 0;
  for (int k = 0; k < steps; ++k) {
    const double t = k * dt;
    const double L = sys.box.length(t);
    sys.update_neighbors(L);
    if (sys.neighbors.builds() != builds_seen) {
      builds_seen = sys.neighbors.builds();
      BOOST_TEST_REQUIRE((listed_pairs(sys.neighbors) == oracle(sys, L, skin)));
    }
    const PairSet listed = listed_pairs(sys.neighbors);
    const PairSet contacts = oracle(sys, L, 0.0);
    contacts_checked += contacts.size();
    BOOST_TEST_REQUIRE(
        std::includes(listed.begin(), listed.end(), contacts.begin(), contacts.end()));
    stepper.step(sys, t, dt);
  }
  BOOST_TEST_MESSAGE(D << "D: " << builds_seen << " builds, " << contacts_checked << " contacts");
  BOOST_TEST(builds_seen >= 3u);  // the test exercised rebuilds
  BOOST_TEST(contacts_checked > 0u);
}

}  // namespace

BOOST_AUTO_TEST_CASE(cells_match_brute_force) {
  auto check = [](auto sys) {
    const double L = sys.box.length(0.0);
    sys.neighbors.build(sys.particles, sys.species, L);
    BOOST_TEST(sys.neighbors.used_cells());
    BOOST_TEST((listed_pairs(sys.neighbors) == oracle(sys, L, sys.neighbors.skin())));
  };
  check(test::random_system<2>(800, 0.8, 1));
  check(test::random_system<3>(800, 0.6, 2));
}

BOOST_AUTO_TEST_CASE(small_box_falls_back_to_all_pairs) {
  // L = 4.6 > 2 (1.4 + 0.3) but fewer than 3 cells per side.
  System<2> sys = test::random_system<2>(16, 0.8, 3);
  const double L = sys.box.length(0.0);
  BOOST_TEST_REQUIRE(L > 3.4);
  sys.neighbors.build(sys.particles, sys.species, L);
  BOOST_TEST(!sys.neighbors.used_cells());
  BOOST_TEST((listed_pairs(sys.neighbors) == oracle(sys, L, sys.neighbors.skin())));
}

BOOST_AUTO_TEST_CASE(no_missed_contact_while_compressing_2d) {
  compress_and_compare<2>(400, 0.78, 0.3, 400);
}

BOOST_AUTO_TEST_CASE(no_missed_contact_while_compressing_3d) {
  compress_and_compare<3>(400, 0.58, 0.2, 300);
}

BOOST_AUTO_TEST_CASE(rebuild_criterion_accounts_for_box_shrink) {
  // No particle moves in scaled coordinates, but shrinking the box by more than
  // skin / (d_max + skin) eats the margin: a rebuild must be requested.
  System<2> sys = test::random_system<2>(200, 0.5, 4);
  const double L = sys.box.length(0.0);
  sys.neighbors.build(sys.particles, sys.species, L);
  const double limit = 0.3 / (1.4 + 0.3);
  BOOST_TEST(!sys.neighbors.needs_rebuild(sys.particles, L * (1.0 - 0.9 * limit)));
  BOOST_TEST(sys.neighbors.needs_rebuild(sys.particles, L * (1.0 - 1.1 * limit)));
}
