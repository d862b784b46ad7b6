// The paired (two pairs per SSE2 instruction) pair loop gives the reference one-pair-at-a-time
// loop's forces bit for bit: on jammed and dilute packings in 2D and 3D, with odd pair counts,
// rows split across blocks, and rows longer than a block (a huge skin).
#define BOOST_TEST_MODULE pair_forces
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>

#include "helpers.hpp"
#include "sim/dynamics/pair_forces.hpp"

using namespace jam;

namespace {

template <int D>
std::array<std::vector<double>, D> forces(const System<D>& sys, bool paired, std::size_t first,
                                          std::size_t last) {
  std::array<std::vector<double>, D> f;
  std::array<double*, D> ptr;
  for (int d = 0; d < D; ++d) {
    f[d].assign(sys.size(), 0.0);
    ptr[d] = f[d].data();
  }
  const auto in = sys.pair_loop_input(sys.box.length(0.0));
#if defined(__SSE2__)
  if (paired) {
    accumulate_pair_forces_paired(in, first, last, ptr);
    return f;
  }
#endif
  (void)paired;
  accumulate_pair_forces_scalar(in, first, last, ptr);
  return f;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

template <int D>
void check(std::size_t n, double phi, std::uint64_t seed, double skin) {
  System<D> sys = test::random_system<D>(n, phi, seed, 0.0, skin);
  sys.update_neighbors(sys.box.length(0.0));
  BOOST_TEST_MESSAGE(D << "D phi " << phi << " skin " << skin << ": " << sys.neighbors.pair_count()
                       << " pairs");
  // All rows, and a range of rows starting and ending mid-list (a thread's block).
  for (auto [first, last] : {std::pair<std::size_t, std::size_t>{0, n},
                             std::pair<std::size_t, std::size_t>{n / 3 + 1, 2 * n / 3}}) {
    const auto reference = forces(sys, false, first, last);
    const auto paired = forces(sys, true, first, last);
    double largest = 0.0;
    for (int d = 0; d < D; ++d) {
      BOOST_TEST(same_bits(paired[d], reference[d]));
      for (double v : reference[d]) largest = std::max(largest, std::abs(v));
    }
    BOOST_TEST(largest > 0.0);  // there were contacts
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(paired_loop_gives_the_reference_bits_2d) {
  check<2>(2002, 0.86, 1, 0.3);  // jammed
  check<2>(1500, 0.6, 2, 0.3);   // dilute: few contacts among listed pairs
  check<2>(2000, 0.8, 3, 15.0);  // rows of up to ~570 pairs, longer than a block
}

BOOST_AUTO_TEST_CASE(paired_loop_gives_the_reference_bits_3d) {
  check<3>(1500, 0.66, 4, 0.3);
  check<3>(1200, 0.5, 5, 0.3);
  check<3>(4000, 0.6, 6, 4.0);
}

BOOST_AUTO_TEST_CASE(odd_pair_count_is_covered) {
  // Small systems: search seeds for an odd number of listed pairs, so that the last pair of
  // the last block goes through the single-pair tail of the paired loop.
  for (std::uint64_t seed = 1; seed < 50; ++seed) {
    System<2> sys = test::random_system<2>(64, 0.85, seed);
    sys.update_neighbors(sys.box.length(0.0));
    if (sys.neighbors.pair_count() % 2 == 1) {
      check<2>(64, 0.85, seed, 0.3);
      return;
    }
  }
  BOOST_FAIL("no seed gave an odd pair count");
}
