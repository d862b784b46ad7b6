// The blocked pair loops (two pairs per SSE2 instruction, four per AVX2 instruction) give the
// reference one-pair-at-a-time loop's forces bit for bit, for every contact law, and set exactly
// the entries they own
// ([first, n)): on jammed and dilute packings in 2D and 3D, with every tail length, rows split
// across blocks, and rows longer than a block (a huge skin).
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>

#include "helpers.hpp"
#include "sim/dynamics/pair_forces.hpp"
#include "sim/model/contact_laws.hpp"

using namespace jam;

namespace {

// Stands in f for entries a form must not touch (below `first`) or must write.
constexpr double kUnwritten = 12345.0;

enum class Form { scalar, sse2, avx2, dispatched };

template <int D, class Contact>
std::array<std::vector<double>, D> forces(const System<D, Contact>& sys, Form form,
                                          std::size_t first, std::size_t last) {
  std::array<std::vector<double>, D> f;
  std::array<double*, D> ptr;
  for (int d = 0; d < D; ++d) {
    f[d].assign(sys.size(), kUnwritten);  // every form must set [first, n) itself
    ptr[d] = f[d].data();
  }
  const std::size_t n = sys.size();
  const auto in = sys.pair_loop_input(sys.box.length(0.0));
  switch (form) {
    case Form::scalar:
      write_pair_forces_scalar(in, first, last, n, ptr);
      break;
    case Form::sse2:
#if defined(__SSE2__)
      write_pair_forces_sse2(in, first, last, n, ptr);
#endif
      break;
    case Form::avx2:
#if defined(JAM_AVX2_FORMS)
      write_pair_forces_avx2(in, first, last, n, ptr);
#endif
      break;
    case Form::dispatched:
      write_pair_forces(in, first, last, n, ptr);
      break;
  }
  return f;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

template <int D, class Contact>
void check(std::size_t n, double phi, std::uint64_t seed, double skin) {
  auto sys = test::random_system<D, Contact>(n, phi, seed, 0.0, skin);
  sys.update_neighbors(sys.box.length(0.0));
  BOOST_TEST_MESSAGE(D << "D phi " << phi << " skin " << skin << ": " << sys.neighbors.pair_count()
                       << " pairs");
  // All rows, a range of rows starting and ending mid-list (a thread's block), and no rows
  // (f[first, n) must still be set, to zero).
  for (auto [first, last] : {std::pair<std::size_t, std::size_t>{0, n},
                             std::pair<std::size_t, std::size_t>{n / 3 + 1, 2 * n / 3},
                             std::pair<std::size_t, std::size_t>{n / 2, n / 2}}) {
    const auto reference = forces(sys, Form::scalar, first, last);
    std::vector<Form> forms{Form::dispatched};
#if defined(__SSE2__)
    forms.push_back(Form::sse2);
#endif
#if defined(JAM_AVX2_FORMS)
    if (cpu_has_avx2()) forms.push_back(Form::avx2);
#endif
    BOOST_TEST_MESSAGE(forms.size()
                       << " blocked forms compared (AVX2 only where the processor has it)");
    for (Form form : forms) {
      const auto blocked = forces(sys, form, first, last);
      for (int d = 0; d < D; ++d) {
        BOOST_TEST(same_bits(blocked[d], reference[d]));
        BOOST_TEST(std::count(blocked[d].begin(), blocked[d].end(), kUnwritten) ==
                   static_cast<std::ptrdiff_t>(first));  // [0, first) untouched, the rest set
      }
    }
    double largest = 0.0;
    for (int d = 0; d < D; ++d)
      for (std::size_t i = first; i < n; ++i)
        largest = std::max(largest, std::abs(reference[d][i]));
    BOOST_TEST((largest > 0.0) == (last > first));  // there were contacts in the rows
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(paired_loop_gives_the_reference_bits_2d, Contact, ContactLaws) {
  check<2, Contact>(2002, 0.86, 1, 0.3);  // jammed
  check<2, Contact>(1500, 0.6, 2, 0.3);   // dilute: few contacts among listed pairs
  check<2, Contact>(2000, 0.8, 3, 15.0);  // rows of up to ~570 pairs, longer than a block
}

BOOST_AUTO_TEST_CASE_TEMPLATE(paired_loop_gives_the_reference_bits_3d, Contact, ContactLaws) {
  check<3, Contact>(1500, 0.66, 4, 0.3);
  check<3, Contact>(1200, 0.5, 5, 0.3);
  check<3, Contact>(4000, 0.6, 6, 4.0);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(every_tail_length_is_covered, Contact, ContactLaws) {
  // Small systems (one block): search seeds for pair counts of every remainder modulo 4, so
  // that the last pairs go through the one-pair tail of the SSE2 (odd count) and AVX2 (1 to 3
  // pairs) first passes.
  std::array<bool, 4> seen{};
  for (std::uint64_t seed = 1; seed < 200; ++seed) {
    System<2> sys = test::random_system<2>(64, 0.85, seed);
    sys.update_neighbors(sys.box.length(0.0));
    const std::size_t remainder = sys.neighbors.pair_count() % 4;
    if (seen[remainder]) continue;
    seen[remainder] = true;
    BOOST_TEST_MESSAGE("pair count " << sys.neighbors.pair_count());
    check<2, Contact>(64, 0.85, seed, 0.3);
  }
  for (std::size_t r = 0; r < 4; ++r)
    BOOST_TEST(seen[r], "no seed gave a pair count = " << r << " mod 4");
}
