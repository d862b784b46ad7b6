// A run split over threads (--threads): the neighbor list and the rebuild decisions are those
// of one thread exactly; the forces agree with one thread and with an O(N^2) sum to round-off;
// and a threaded run repeats itself bit for bit.
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "helpers.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/parallel.hpp"

using namespace jam;

namespace {

// Two threads where the machine has them; the tests still run (and compare one thread with
// itself and with the O(N^2) sum) on a single core.
int two_threads() {
  return std::min(2, available_threads());
}

// Elastic forces by an O(N^2) double loop over all pairs, each pair's force computed from
// the contact law directly: independent of the neighbor list and of the thread split.
template <int D>
std::array<std::vector<double>, D> brute_force_forces(const System<D>& sys, double L) {
  const std::size_t n = sys.size();
  std::array<std::vector<double>, D> f;
  for (auto& c : f) c.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      std::array<double, D> dr;
      const double r = std::sqrt(pair_separation(sys.particles, i, j, L, dr));
      const double d = sys.species.contact_distance[sys.particles.type[i] + sys.particles.type[j]];
      if (r >= d) continue;
      const double magnitude = (1.0 - r / d) / d;  // -dU/dr of U = (1/2)(1 - r/d)^2
      for (int k = 0; k < D; ++k) {
        f[k][i] += magnitude * dr[k] / r;
        f[k][j] -= magnitude * dr[k] / r;
      }
    }
  }
  return f;
}

template <int D>
void forces_agree(std::size_t n, double phi) {
  System<D> serial = test::random_system<D>(n, phi, 11);
  System<D> threaded = serial;
  threaded.set_threads(two_threads());
  const double L = serial.box.length(0.0);
  serial.compute_elastic_forces(L);
  threaded.compute_elastic_forces(L);
  const auto oracle = brute_force_forces(serial, L);
  double largest = 0.0, threads_vs_serial = 0.0, threads_vs_oracle = 0.0;
  for (int d = 0; d < D; ++d) {
    for (std::size_t i = 0; i < n; ++i) {
      largest = std::max(largest, std::abs(oracle[d][i]));
      threads_vs_serial =
          std::max(threads_vs_serial, std::abs(threaded.force[d][i] - serial.force[d][i]));
      threads_vs_oracle =
          std::max(threads_vs_oracle, std::abs(threaded.force[d][i] - oracle[d][i]));
    }
  }
  // A force is a sum of at most ~15 pair terms, each no larger than `largest`; regrouping the
  // sum (two partial forces) or evaluating each term differently (1/r (1/r - 1/d) against
  // (1 - r/d)/(d r)) changes it by a few ulps of that, far below 1e-12 relative. A missing or
  // doubled pair would be off by a whole pair force (~1e-2 of `largest` at least).
  BOOST_TEST_REQUIRE(largest > 0.1);
  BOOST_TEST(threads_vs_serial <= 1e-12 * largest);
  BOOST_TEST(threads_vs_oracle <= 1e-12 * largest);
}

}  // namespace

BOOST_AUTO_TEST_CASE(threaded_list_is_the_serial_list) {
  auto check = [](auto serial) {
    auto threaded = serial;
    threaded.set_threads(two_threads());
    const double L = serial.box.length(0.0);
    serial.update_neighbors(L);
    threaded.update_neighbors(L);
    BOOST_TEST(threaded.neighbors.offsets() == serial.neighbors.offsets());
    BOOST_TEST(threaded.neighbors.neighbors() == serial.neighbors.neighbors());
    BOOST_TEST(serial.neighbors.pair_count() > serial.size());
  };
  check(test::random_system<2>(3000, 0.8, 1));
  check(test::random_system<3>(3000, 0.6, 2));
}

BOOST_AUTO_TEST_CASE(threaded_rebuild_test_decides_as_the_serial_one) {
  // Heun steps at a fast rate, on two threads; before each step the rebuild decision for the
  // current build and positions is taken by two threads and by one.
  System<2> sys = test::random_system<2>(2000, 0.8, 3, 1e-2);
  sys.set_threads(two_threads());
  OverdampedHeun<2> stepper(sys.size());
  int rebuilds_wanted = 0;
  for (int k = 0; k < 200; ++k) {
    const double L = sys.box.length(0.1 * k);
    NeighborList<2> one_thread = sys.neighbors;  // the same build, tested by one thread
    one_thread.set_threads(1);
    const bool serial = one_thread.needs_rebuild(sys.particles, L);
    BOOST_TEST(sys.neighbors.needs_rebuild(sys.particles, L) == serial);
    rebuilds_wanted += serial;
    stepper.step(sys, 0.1 * k, 0.1);
  }
  BOOST_TEST(rebuilds_wanted > 0);  // both answers occurred
  BOOST_TEST(rebuilds_wanted < 200);
}

BOOST_AUTO_TEST_CASE(threaded_forces_match_serial_and_brute_force_2d) {
  forces_agree<2>(1500, 0.86);
}
BOOST_AUTO_TEST_CASE(threaded_forces_match_serial_and_brute_force_3d) {
  forces_agree<3>(1500, 0.66);
}

BOOST_AUTO_TEST_CASE(threaded_run_repeats_bit_for_bit) {
  System<3> a = test::random_system<3>(2000, 0.62, 4, 1e-3);
  a.set_threads(two_threads());
  System<3> b = a;
  OverdampedHeun<3> sa(a.size()), sb(b.size());
  for (int k = 0; k < 300; ++k) {
    sa.step(a, 0.1 * k, 0.1);
    sb.step(b, 0.1 * k, 0.1);
  }
  for (int d = 0; d < 3; ++d) BOOST_TEST((a.particles.s[d] == b.particles.s[d]));
  BOOST_TEST(a.neighbors.builds() > 1u);
}

BOOST_AUTO_TEST_CASE(thread_count_is_checked) {
  System<2> sys = test::random_system<2>(100, 0.8, 5);
  BOOST_CHECK_THROW(sys.set_threads(0), std::invalid_argument);
  BOOST_CHECK_THROW(sys.set_threads(available_threads() + 1), std::invalid_argument);
}
