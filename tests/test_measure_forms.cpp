// measure() (sim/observables/observables.hpp) with its blocked first pass
// (sim/observables/pair_measure.hpp) gives the bits of the one-pair-at-a-time computation it
// replaced, written out below as the oracle: pressure, stress, Z, energy and the rattler
// analysis, for every contact law, in 2D and 3D, on jammed and dilute packings and a list
// whose length is not a multiple of the block or of four. The scalar and AVX2 forms of the
// first pass agree bit for bit on every block. Without the whole stress tensor the pressure
// and the rest keep their bits.
#include <boost/test/unit_test.hpp>
#include <cstring>

#include "helpers.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/observables/observables.hpp"

using namespace jam;

namespace {

// The measurement as it was written before the blocked pass: every listed pair, its own
// separation, the contact test, energy and stress.
template <int D, class Contact>
Observables<D> oracle(System<D, Contact>& sys, double t) {
  const double box_length = sys.box.length(t);
  sys.update_neighbors(box_length);
  const auto& p = sys.particles;
  const auto& offsets = sys.neighbors.offsets();
  const auto& nbr = sys.neighbors.neighbors();
  Observables<D> obs;
  double energy = 0.0;
  std::size_t contacts = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> contact_pairs;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = nbr[k];
      std::array<double, D> dr;
      const double r2 = pair_separation(p, i, j, box_length, dr);
      const int pair = p.type[i] + p.type[j];
      if (!sys.contact.in_contact(r2, pair)) continue;
      ++contacts;
      energy += sys.contact.energy(r2, pair);
      const double c = sys.contact.force_over_r(r2, pair);
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) obs.stress[a][b] += c * dr[a] * dr[b];
      contact_pairs.emplace_back(static_cast<std::uint32_t>(i), j);
    }
  }
  const RattlerAnalysis r = find_rattlers(sys.size(), contact_pairs, D + 1);
  obs.contacts_per_particle_no_rattlers = r.contacts_per_particle;
  obs.rattler_fraction = static_cast<double>(r.rattlers) / static_cast<double>(sys.size());
  const double volume = std::pow(box_length, D);
  double trace = 0.0;
  for (int a = 0; a < D; ++a) {
    for (int b = 0; b < D; ++b) obs.stress[a][b] /= volume;
    trace += obs.stress[a][a];
  }
  obs.pressure = trace / D;
  obs.contacts_per_particle = 2.0 * static_cast<double>(contacts) / static_cast<double>(sys.size());
  obs.energy_per_particle = energy / static_cast<double>(sys.size());
  return obs;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

template <int D, class Contact>
void check(std::size_t n, double phi, std::uint64_t seed) {
  auto sys = test::random_system<D, Contact>(n, phi, seed);
  const Observables<D> expected = oracle(sys, 0.0);
  const Observables<D> got = measure(sys, 0.0, true);
  BOOST_TEST_MESSAGE(D << "D phi " << phi << ": " << sys.neighbors.pair_count() << " pairs, Z "
                       << got.contacts_per_particle << ", p " << got.pressure);
  BOOST_TEST(expected.contacts_per_particle > 0.0);  // there was something to measure
  BOOST_TEST(same_bits(got.pressure, expected.pressure));
  BOOST_TEST(same_bits(got.energy_per_particle, expected.energy_per_particle));
  BOOST_TEST(same_bits(got.contacts_per_particle, expected.contacts_per_particle));
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) BOOST_TEST(same_bits(got.stress[a][b], expected.stress[a][b]));
  // The rattler analysis sees the same contacts.
  BOOST_TEST(same_bits(got.contacts_per_particle_no_rattlers,
                       expected.contacts_per_particle_no_rattlers));
  BOOST_TEST(same_bits(got.rattler_fraction, expected.rattler_fraction));

  // Without the whole tensor (runs without --stress): the pressure, energy, Z and diagonal
  // with the same bits, the off-diagonal entries 0.
  const Observables<D> diagonal = measure(sys, 0.0, false, false);
  BOOST_TEST(same_bits(diagonal.pressure, expected.pressure));
  BOOST_TEST(same_bits(diagonal.energy_per_particle, expected.energy_per_particle));
  BOOST_TEST(same_bits(diagonal.contacts_per_particle, expected.contacts_per_particle));
  for (int a = 0; a < D; ++a) {
    for (int b = 0; b < D; ++b) {
      if (a == b) BOOST_TEST(same_bits(diagonal.stress[a][a], expected.stress[a][a]));
      if (a != b) BOOST_TEST(diagonal.stress[a][b] == 0.0);
    }
  }

  // The forms of the first pass, block by block (a last block shorter than the others).
  const auto in = sys.pair_loop_input(sys.box.length(0.0));
  const std::uint32_t pairs = sys.neighbors.offsets()[n];
  BOOST_TEST_REQUIRE(pairs % kMeasureBlockPairs != 0u);
  for (std::uint32_t k0 = 0; k0 < pairs; k0 += kMeasureBlockPairs) {
    const std::uint32_t k1 = std::min(pairs, k0 + kMeasureBlockPairs);
    MeasureBlock<D> scalar{}, dispatched{};
    measure_pairs_scalar(in, k0, k1, scalar);
    measure_pairs(in, k0, k1, dispatched);
    BOOST_TEST(std::memcmp(&scalar, &dispatched, sizeof scalar) == 0);
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(blocked_measure_gives_the_oracle_bits, Contact, ContactLaws) {
  check<2, Contact>(1022, 0.86, 3);
  check<2, Contact>(510, 0.5, 4);
  check<3, Contact>(1022, 0.66, 5);
  check<3, Contact>(514, 0.4, 6);
}
