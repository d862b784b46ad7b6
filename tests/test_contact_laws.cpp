// Each contact law against independent computations: its force is -dU/dr and its stiffness
// d^2U/dr^2 (central finite differences of its energy), its values equal the closed forms
// written with std::pow, it is exactly zero out of contact and finite at r = 0, its packed
// SSE2 / AVX2 f/r give the scalar bits, "in contact" is where the force is nonzero, and its
// LAMMPS table is -dU/dr row by row; the harmonic table equals the one written independently
// by reference/lammps/make_table.py.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>

#include "sim/io/lammps_table.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/model/species.hpp"

using namespace jam;

namespace {

/// U(r) as the law's energy() of r^2.
template <class Contact>
double energy_of_r(const Contact& law, double r, int pair) {
  return law.energy(r * r, pair);
}

/// A table file's sections: name -> rows (r, U, f).
std::map<std::string, std::vector<std::array<double, 3>>> read_table(std::istream& in) {
  std::map<std::string, std::vector<std::array<double, 3>>> sections;
  std::string line, name;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    if (line == "SS" || line == "SB" || line == "BB") {
      name = line;
      continue;
    }
    if (line[0] == 'N') continue;
    long k;
    std::array<double, 3> v;
    if (row >> k >> v[0] >> v[1] >> v[2]) sections[name].push_back(v);
  }
  return sections;
}

#if defined(JAM_AVX2_FORMS)
/// The law's four-wide f/r of r2[0..3], stored into out.
template <class Contact>
__attribute__((target("avx2"))) void packed_avx2(const Contact& law, const double* r2,
                                                 std::array<int, 4> pair, double* out) {
  _mm256_store_pd(out, law.force_over_r(_mm256_set_pd(r2[3], r2[2], r2[1], r2[0]), pair));
}
#endif

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(force_is_minus_dU_dr_and_stiffness_is_d2U_dr2, Contact, ContactLaws) {
  const Species<2> species;
  const Contact law(species);
  for (int pair = 0; pair < 3; ++pair) {
    const double d = species.contact_distance[pair];
    for (double overlap : {1e-3, 0.01, 0.05, 0.2}) {
      const double r = d * (1.0 - overlap);
      // h = 1e-6 d: truncation O(h^2 U''') ~ 1e-12 relative, round-off 1e-16 U / h ~ 1e-10 f
      // at the smallest overlap; 1e-6 relative leaves room and still sees a factor 1.5 or an
      // exponent off by 1/2.
      const double h = 1e-6 * d;
      const double f_fd =
          -(energy_of_r(law, r + h, pair) - energy_of_r(law, r - h, pair)) / (2.0 * h);
      const double f = law.force_over_r(r * r, pair) * r;
      BOOST_TEST(f == f_fd, boost::test_tools::tolerance(1e-6));
      const double k_fd = -(law.force_over_r((r + h) * (r + h), pair) * (r + h) -
                            law.force_over_r((r - h) * (r - h), pair) * (r - h)) /
                          (2.0 * h);
      BOOST_TEST(law.radial_stiffness(r * r, pair) == k_fd, boost::test_tools::tolerance(1e-6));
      // The LAMMPS table's functions are the same law, up to the round-off of 1 - r/d, which
      // is relative eps / overlap (r and d agree to ~overlap), a few times over.
      const double roundoff = 20.0 * std::numeric_limits<double>::epsilon() / overlap;
      BOOST_TEST(Contact::force_at(r, d) == f, boost::test_tools::tolerance(roundoff));
      BOOST_TEST(Contact::energy_at(r, d) == law.energy(r * r, pair),
                 boost::test_tools::tolerance(roundoff));
    }
  }
}

BOOST_AUTO_TEST_CASE(closed_forms) {
  // Written with std::pow, independently of the laws' sqrt-based forms.
  const Species<3> species;
  const HarmonicContact harmonic(species);
  const HertzianContact hertzian(species);
  for (int pair = 0; pair < 3; ++pair) {
    const double d = species.contact_distance[pair];
    for (double overlap : {1e-4, 0.03, 0.3}) {
      const double r = d * (1.0 - overlap);
      // 1 - r/d carries round-off of relative eps / overlap (a few times over); an error of
      // the law's form (a factor, an exponent) is >= 1e-2 here.
      const auto tolerance =
          boost::test_tools::tolerance(20.0 * std::numeric_limits<double>::epsilon() / overlap);
      BOOST_TEST(harmonic.force_over_r(r * r, pair) * r == overlap / d, tolerance);
      BOOST_TEST(harmonic.energy(r * r, pair) == 0.5 * std::pow(overlap, 2.0), tolerance);
      BOOST_TEST(hertzian.force_over_r(r * r, pair) * r == std::pow(overlap, 1.5) / d, tolerance);
      BOOST_TEST(hertzian.energy(r * r, pair) == 0.4 * std::pow(overlap, 2.5), tolerance);
      BOOST_TEST(hertzian.radial_stiffness(r * r, pair) == 1.5 * std::pow(overlap, 0.5) / (d * d),
                 tolerance);
    }
  }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(zero_out_of_contact_and_finite_at_zero, Contact, ContactLaws) {
  const Species<2> species;
  const Contact law(species);
  for (int pair = 0; pair < 3; ++pair) {
    const double d = species.contact_distance[pair];
    for (double r : {d, std::nextafter(d, 2.0 * d), 1.5 * d, 1e3 * d}) {
      BOOST_TEST(law.force_over_r(r * r, pair) == 0.0);
      BOOST_TEST(law.energy(r * r, pair) == 0.0);
      BOOST_TEST(!law.in_contact(r * r, pair));
    }
    BOOST_TEST(std::isfinite(law.force_over_r(0.0, pair)));
    BOOST_TEST(law.force_over_r(0.0, pair) * 0.0 == 0.0);
    BOOST_TEST(law.in_contact(0.25 * d * d, pair));
  }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(in_contact_is_where_the_force_is, Contact, ContactLaws) {
  // The one definition: pairs within an ulp of d are in contact exactly when the force loop
  // gives them a force, never by a second test that could disagree.
  const Species<2> species;
  const Contact law(species);
  for (int pair = 0; pair < 3; ++pair) {
    double r = species.contact_distance[pair];
    for (int k = 0; k < 64; ++k, r = std::nextafter(r, 0.0)) {
      BOOST_TEST(law.in_contact(r * r, pair) == (law.force_over_r(r * r, pair) > 0.0));
    }
  }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(packed_forms_give_the_scalar_bits, Contact, ContactLaws) {
  const Species<3> species;
  const Contact law(species);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.6);
  std::vector<double> r2;
  for (int k = 0; k < 4000; ++k) r2.push_back(std::pow(u(rng), 2));
  for (double d : species.contact_distance) {  // contact edges and their neighbours
    r2.insert(r2.end(), {d * d, std::nextafter(d * d, 0.0), std::nextafter(d * d, 9.0), 0.0});
  }
  while (r2.size() % 4) r2.push_back(0.5);
  auto bits = [](double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  int compared = 0;
  for (std::size_t k = 0; k < r2.size(); k += 4) {
    const std::array<int, 4> pair{int(k % 3), int((k + 1) % 3), int((k + 2) % 3), int((k + 3) % 3)};
#if defined(__SSE2__)
    alignas(16) double two[2];
    _mm_store_pd(two, law.force_over_r(_mm_set_pd(r2[k + 1], r2[k]), {pair[0], pair[1]}));
    for (int q = 0; q < 2; ++q) {
      BOOST_TEST(bits(two[q]) == bits(law.force_over_r(r2[k + q], pair[q])));
      ++compared;
    }
#endif
#if defined(JAM_AVX2_FORMS)
    if (cpu_has_avx2()) {
      alignas(32) double four[4];
      packed_avx2(law, &r2[k], pair, four);
      for (int q = 0; q < 4; ++q) {
        BOOST_TEST(bits(four[q]) == bits(law.force_over_r(r2[k + q], pair[q])));
        ++compared;
      }
    }
#endif
  }
  BOOST_TEST_MESSAGE(compared << " packed values compared");
}

BOOST_AUTO_TEST_CASE(harmonic_table_equals_the_independently_written_one) {
  std::ifstream stored(std::string(JAM_SOURCE_DIR) + "/reference/lammps/harmonic_contact.table");
  BOOST_TEST_REQUIRE(stored.good());
  std::istringstream generated(lammps_table<HarmonicContact>(kPaperDiameterRatio));
  const auto a = read_table(stored), b = read_table(generated);
  BOOST_TEST_REQUIRE(a.size() == 3u);
  for (const auto& [name, rows] : a) {
    BOOST_TEST_REQUIRE(b.at(name).size() == rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k)
      for (int c = 0; c < 3; ++c) BOOST_TEST(b.at(name)[k][c] == rows[k][c]);  // exactly
  }
}

BOOST_AUTO_TEST_CASE_TEMPLATE(table_force_column_is_minus_dU_dr, Contact, ContactLaws) {
  std::istringstream text(lammps_table<Contact>(kPaperDiameterRatio));
  const auto sections = read_table(text);
  BOOST_TEST_REQUIRE(sections.size() == 3u);
  for (const auto& [name, rows] : sections) {
    BOOST_TEST_REQUIRE(rows.size() == static_cast<std::size_t>(Contact::kTablePoints));
    BOOST_TEST(rows.back()[1] == 0.0);  // U and f vanish at r = d
    BOOST_TEST(rows.back()[2] == 0.0);
    const double f_max = rows.front()[2];
    // Central differences between rows, h = 0.6 d / (points - 1): truncation h^2 U''' / 6,
    // below 1e-4 f_max for both tables away from the last rows (where U''' of the Hertzian
    // law grows as delta^(-1/2)).
    for (std::size_t k = 1; k + 10 < rows.size(); ++k) {
      const double f_fd = -(rows[k + 1][1] - rows[k - 1][1]) / (rows[k + 1][0] - rows[k - 1][0]);
      BOOST_TEST(std::abs(f_fd - rows[k][2]) <= 1e-4 * f_max);
    }
  }
}
