// One stored reference per contact law and dimension (reference/contact/<law>-<D>d.ref, in the
// manner of LAMMPS's unittest YAML files): a fixed configuration of 48 overlapping particles
// with its forces, stress, pressure, energy and Z, and the tolerance they are compared with.
// Every form of the pair loop (one pair at a time, SSE2, AVX2, the dispatched one), 1 and 2
// threads, and a checkpoint round trip of the configuration must give them.
// Regenerate (after a deliberate change of a law): JAM_REGENERATE_REFERENCE=1
// test_contact_reference
#include <fmt/format.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "helpers.hpp"
#include "sim/dynamics/pair_forces.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/observables/observables.hpp"

using namespace jam;
namespace fs = std::filesystem;

namespace {

// Relative to the largest force (forces) or to the value (observables). The reference is
// written by this code; every operation of a law is correctly rounded IEEE arithmetic without
// FMA contraction, so the same build gives the same bits. 1e-12 allows a compiler that
// contracts or reorders a sum of ~10 contacts (a few ulp each) and still sees any change of a
// law's constants or exponents (>= 1e-3 here).
constexpr double kTolerance = 1e-12;
constexpr std::size_t kParticles = 48;

template <int D, class Contact>
struct Reference {
  double box_length = 0;
  ParticleData<D> particles;
  std::array<std::vector<double>, D> force;
  Observables<D> obs;
};

template <int D, class Contact>
fs::path reference_path() {
  return fs::path(JAM_SOURCE_DIR) / "reference" / "contact" /
         fmt::format("{}-{}d.ref", Contact::kName, D);
}

template <int D, class Contact>
System<D, Contact> system_of(const Reference<D, Contact>& ref) {
  const Species<D> species;
  CompressingBox<D> box{ref.box_length, 0.0, total_particle_volume(ref.particles, species)};
  return System<D, Contact>(ref.particles, species, box, 0.3);
}

template <int D, class Contact>
void write_reference() {
  const double phi = D == 2 ? 0.90 : 0.72;  // well above jamming: many contacts of every kind
  auto sys = test::random_system<D, Contact>(kParticles, phi, 2024);
  const double length = sys.box.length(0.0);
  sys.compute_elastic_forces(length);
  const auto obs = measure(sys, 0.0, false);
  std::ofstream out(reference_path<D, Contact>());
  out << fmt::format(
      "# jam contact-law reference: {} law ({}), {}D\n"
      "# {} particles at phi {}, their forces, stress, pressure, energy and Z.\n"
      "# Checked by tests/test_contact_reference.cpp for every pair-loop form, 1 and 2 threads\n"
      "# and a checkpoint round trip, within the tolerance (relative; why: that file).\n"
      "# Regenerate: JAM_REGENERATE_REFERENCE=1 build/tests/test_contact_reference\n",
      Contact::kName, Contact::kFormula, D, kParticles, phi);
  out << fmt::format("tolerance {}\nbox_length {:.17g}\n", kTolerance, length);
  out << fmt::format(
      "energy_per_particle {:.17g}\npressure {:.17g}\ncontacts_per_particle {:.17g}\n",
      obs.energy_per_particle, obs.pressure, obs.contacts_per_particle);
  out << "stress";
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) out << fmt::format(" {:.17g}", obs.stress[a][b]);
  out << "\n# particle: type, scaled position (D), force (D)\n";
  for (std::size_t i = 0; i < kParticles; ++i) {
    out << "particle " << int(sys.particles.type[i]);
    for (int d = 0; d < D; ++d) out << fmt::format(" {:.17g}", sys.particles.s[d][i]);
    for (int d = 0; d < D; ++d) out << fmt::format(" {:.17g}", sys.force[d][i]);
    out << "\n";
  }
}

template <int D, class Contact>
Reference<D, Contact> read_reference() {
  const fs::path path = reference_path<D, Contact>();
  std::ifstream in(path);
  BOOST_TEST_REQUIRE(in.good(), "missing " << path);
  Reference<D, Contact> r;
  r.particles.resize(kParticles);
  for (auto& f : r.force) f.assign(kParticles, 0.0);
  std::string line, key;
  std::size_t i = 0;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    if (!(row >> key) || key[0] == '#') continue;
    if (key == "box_length") row >> r.box_length;
    if (key == "energy_per_particle") row >> r.obs.energy_per_particle;
    if (key == "pressure") row >> r.obs.pressure;
    if (key == "contacts_per_particle") row >> r.obs.contacts_per_particle;
    if (key == "stress")
      for (auto& rowa : r.obs.stress)
        for (double& v : rowa) row >> v;
    if (key == "particle") {
      BOOST_TEST_REQUIRE(i < kParticles);
      int type = 0;
      row >> type;
      r.particles.type[i] = static_cast<std::uint8_t>(type);
      r.particles.id[i] = static_cast<std::uint32_t>(i + 1);
      for (int d = 0; d < D; ++d) row >> r.particles.s[d][i];
      for (int d = 0; d < D; ++d) row >> r.force[d][i];
      ++i;
    }
  }
  BOOST_TEST_REQUIRE(i == kParticles);
  return r;
}

template <int D>
void check_forces(const std::array<std::vector<double>, D>& got,
                  const std::array<std::vector<double>, D>& expected, const std::string& how) {
  double largest = 0.0, worst = 0.0;
  for (int d = 0; d < D; ++d)
    for (double f : expected[d]) largest = std::max(largest, std::abs(f));
  for (int d = 0; d < D; ++d)
    for (std::size_t i = 0; i < kParticles; ++i)
      worst = std::max(worst, std::abs(got[d][i] - expected[d][i]));
  BOOST_TEST_REQUIRE(largest > 0.0);
  BOOST_TEST(worst <= kTolerance * largest,
             how << ": largest difference " << worst << " of " << largest);
}

template <int D, class Contact>
void check_case() {
  if (std::getenv("JAM_REGENERATE_REFERENCE")) write_reference<D, Contact>();
  const auto ref = read_reference<D, Contact>();
  auto sys = system_of(ref);
  const double length = ref.box_length;
  sys.update_neighbors(length);
  const std::size_t n = sys.size();
  auto forces = [&](auto write) {
    std::array<std::vector<double>, D> f;
    std::array<double*, D> ptr;
    for (int d = 0; d < D; ++d) {
      f[d].assign(n, 0.0);
      ptr[d] = f[d].data();
    }
    write(sys.pair_loop_input(length), ptr);
    return f;
  };
  check_forces<D>(
      forces([&](const auto& in, const auto& f) { write_pair_forces_scalar(in, 0, n, n, f); }),
      ref.force, "one pair at a time");
#if defined(__SSE2__)
  check_forces<D>(
      forces([&](const auto& in, const auto& f) { write_pair_forces_sse2(in, 0, n, n, f); }),
      ref.force, "SSE2");
#endif
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    check_forces<D>(
        forces([&](const auto& in, const auto& f) { write_pair_forces_avx2(in, 0, n, n, f); }),
        ref.force, "AVX2");
  }
#endif
  for (int threads = 1; threads <= std::min(2, available_threads()); ++threads) {
    sys.set_threads(threads);
    sys.compute_elastic_forces(length);
    check_forces<D>(sys.force, ref.force, fmt::format("{} thread(s)", threads));
  }
  const auto obs = measure(sys, 0.0, false);
  BOOST_TEST(obs.energy_per_particle == ref.obs.energy_per_particle,
             boost::test_tools::tolerance(kTolerance));
  BOOST_TEST(obs.pressure == ref.obs.pressure, boost::test_tools::tolerance(kTolerance));
  BOOST_TEST(obs.contacts_per_particle == ref.obs.contacts_per_particle);  // integers / N
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      BOOST_TEST(obs.stress[a][b] == ref.obs.stress[a][b],
                 boost::test_tools::tolerance(kTolerance));

  // Through a checkpoint and back: the configuration a resumed run continues from.
  const fs::path dir = fs::temp_directory_path() / fmt::format("jam_contact_ref_{}", ::getpid());
  fs::create_directories(dir);
  const std::string path = (dir / "state.checkpoint").string();
  write_checkpoint<D>(path, "reference", RunState<D>{}, ref.particles, StepperState{});
  const auto back = read_checkpoint<D>(path, "reference");
  fs::remove_all(dir);
  BOOST_TEST_REQUIRE(back.has_value());
  Reference<D, Contact> restored = ref;
  restored.particles = back->particles;
  auto resumed = system_of(restored);
  resumed.compute_elastic_forces(length);
  check_forces<D>(resumed.force, ref.force, "after a checkpoint round trip");
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(reference_2d, Contact, ContactLaws) {
  check_case<2, Contact>();
}
BOOST_AUTO_TEST_CASE_TEMPLATE(reference_3d, Contact, ContactLaws) {
  check_case<3, Contact>();
}
