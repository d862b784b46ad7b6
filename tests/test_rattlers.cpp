// Iterative rattler removal on small contact graphs with known answers.
#include <boost/test/unit_test.hpp>

#include "sim/observables/rattlers.hpp"

using namespace jam;
using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

BOOST_AUTO_TEST_CASE(complete_graph_of_four_is_stable_in_2d) {
  // K4: every particle has 3 = D + 1 contacts.
  const Pairs k4 = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  const auto r = find_rattlers(4, k4, 3);
  BOOST_TEST(r.rattlers == 0u);
  BOOST_TEST(r.contacts_per_particle == 3.0);
}

BOOST_AUTO_TEST_CASE(dangling_chain_peels_off_in_cascade) {
  // K4 plus a chain 3-4-5: 5 has one contact, once removed 4 has one, then the K4 remains.
  Pairs g = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}, {3, 4}, {4, 5}};
  const auto r = find_rattlers(6, g, 3);
  BOOST_TEST(r.rattlers == 2u);
  BOOST_TEST(r.is_rattler[4]);
  BOOST_TEST(r.is_rattler[5]);
  BOOST_TEST(r.contacts_per_particle == 3.0);  // 6 contacts among 4 particles
}

BOOST_AUTO_TEST_CASE(removal_can_destabilise_a_cluster) {
  // A 4-cycle with one diagonal: 1 and 3 have two contacts -> removed, leaving 0 and 2 with
  // one contact each -> removed too. Everything is a rattler.
  const Pairs g = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}};
  const auto r = find_rattlers(4, g, 3);
  BOOST_TEST(r.rattlers == 4u);
  BOOST_TEST(r.contacts_per_particle == 0.0);
}

BOOST_AUTO_TEST_CASE(isolated_particles_and_3d_threshold) {
  // K4 in 3D needs 4 contacts: all four are rattlers; an isolated particle is one too.
  const Pairs k4 = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  const auto r = find_rattlers(5, k4, 4);
  BOOST_TEST(r.rattlers == 5u);
  // K5 in 3D: each has 4 contacts, the isolated sixth particle is the only rattler.
  Pairs k5;
  for (std::uint32_t i = 0; i < 5; ++i)
    for (std::uint32_t j = i + 1; j < 5; ++j) k5.emplace_back(i, j);
  const auto r5 = find_rattlers(6, k5, 4);
  BOOST_TEST(r5.rattlers == 1u);
  BOOST_TEST(r5.is_rattler[5]);
  BOOST_TEST(r5.contacts_per_particle == 4.0);
}
