// The diameter ratio (--diameter-ratio, 1.0 to 2.0) without loss of correctness: the packing
// fraction of the start is the one asked for, the cell-list Verlet list equals the O(N^2)
// search and keeps every contact while the box shrinks (cells are sized by the big diameter),
// the stability bound is the closed form for two big particles, and `jam sim` runs at both ends
// of the range and refuses values outside it.
#include <unistd.h>

#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "pair_sets.hpp"
#include "process.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/stability.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/neighbor/brute_force_pairs.hpp"
#include "sim/observables/observables.hpp"

namespace fs = std::filesystem;
using jam::testing::listed_pairs;
using jam::testing::PairSet;

namespace {

template <int D>
jam::System<D> random_system(std::size_t n, double phi, double ratio, double rate) {
  jam::ParticleData<D> p = jam::random_configuration<D>(n, 9);
  jam::Species<D> species(ratio);
  const double volume = jam::total_particle_volume(p, species);
  jam::CompressingBox<D> box{jam::CompressingBox<D>::length_for_packing(volume, phi), rate, volume};
  return jam::System<D>(std::move(p), species, box, 0.3);
}

template <int D>
void neighbors_at_ratio(double ratio, double phi) {
  auto sys = random_system<D>(256, phi, ratio, 1e-2);
  BOOST_TEST(sys.box.packing_fraction(0.0) == phi, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(sys.species.max_contact_distance == std::max(1.0, ratio));
  jam::OverdampedEuler<D> stepper(sys.size());
  std::size_t builds = 0, contacts_seen = 0;
  for (int k = 0; k < 200; ++k) {
    const double t = k * 0.05, L = sys.box.length(t);
    sys.update_neighbors(L);
    if (sys.neighbors.builds() != builds) {
      builds = sys.neighbors.builds();
      const auto v = jam::brute_force_pairs(sys.particles, sys.species, L, 0.3);
      BOOST_TEST_REQUIRE((listed_pairs(sys.neighbors) == PairSet(v.begin(), v.end())));
    }
    const auto c = jam::brute_force_pairs(sys.particles, sys.species, L, 0.0);
    const PairSet l = listed_pairs(sys.neighbors);
    contacts_seen += c.size();
    BOOST_TEST_REQUIRE(std::all_of(c.begin(), c.end(), [&](auto pr) { return l.count(pr); }));
    stepper.step(sys, t, 0.05);
  }
  BOOST_TEST(builds >= 2u);
  BOOST_TEST(contacts_seen > 0u);
}

/// The oracle of the rattler rule: contacts from the O(N^2) search (r < d_ij), then particles
/// with fewer than D + 1 contacts among those left dropped until none is. Written apart from
/// sim/observables/rattlers.hpp; returns {rattlers, Z over the non-rattlers}.
template <int D>
std::pair<std::size_t, double> rattlers_by_hand(const jam::System<D>& sys, double box_length) {
  const auto contacts = jam::brute_force_pairs(sys.particles, sys.species, box_length, 0.0);
  std::vector<bool> gone(sys.size(), false);
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<int> degree(sys.size(), 0);
    for (auto [i, j] : contacts)
      if (!gone[i] && !gone[j]) ++degree[i], ++degree[j];
    for (std::size_t i = 0; i < sys.size(); ++i)
      if (!gone[i] && degree[i] < D + 1) gone[i] = changed = true;
  }
  std::size_t left = 0, kept_contacts = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) left += !gone[i];
  for (auto [i, j] : contacts) kept_contacts += !gone[i] && !gone[j];
  return {sys.size() - left, left ? 2.0 * double(kept_contacts) / double(left) : 0.0};
}

template <int D>
void rattlers_at_ratio(double ratio, double phi) {
  auto sys = random_system<D>(512, phi, ratio, 0.0);
  const auto obs = jam::measure(sys, 0.0, true);
  const auto [rattlers, z] = rattlers_by_hand(sys, sys.box.length(0.0));
  // Both outcomes occur at these packings, so the count is a real comparison, not 0 = 0.
  BOOST_TEST_REQUIRE(rattlers > 0u);
  BOOST_TEST_REQUIRE(rattlers < sys.size());
  BOOST_TEST(obs.rattler_fraction == double(rattlers) / double(sys.size()));
  BOOST_TEST(obs.contacts_per_particle_no_rattlers == z, boost::test_tools::tolerance(1e-12));
}

}  // namespace

// The rattler rule counts contacts only: at every diameter ratio it removes what the contact
// graph of the O(N^2) search says, whatever the sizes that made the graph.
BOOST_AUTO_TEST_CASE(rattlers_follow_the_contact_graph_at_any_ratio) {
  for (double ratio : {1.0, 1.4, 2.0}) {
    BOOST_TEST_CONTEXT("ratio " << ratio) {
      rattlers_at_ratio<2>(ratio, 0.80);
      rattlers_at_ratio<3>(ratio, 0.60);
    }
  }
}

BOOST_AUTO_TEST_CASE(neighbor_list_and_packing) {
  for (double ratio : {1.0, 1.4, 2.0}) {
    BOOST_TEST_CONTEXT("ratio " << ratio) {
      neighbors_at_ratio<2>(ratio, 0.8);
      neighbors_at_ratio<3>(ratio, 0.6);
    }
  }
}

// Two big particles: lambda = 2 k / gamma_b, k = 1 / ratio^2, gamma_b = (2/D) ratio^D.
BOOST_AUTO_TEST_CASE(stability_bound_of_two_big_particles) {
  for (double ratio : {1.0, 2.0}) {
    jam::ParticleData<2> p;
    p.resize(2);
    p.s[0] = {0.5, 0.5 + 0.9 * ratio / 10.0};
    p.s[1] = {0.5, 0.5};
    p.type = {1, 1};
    p.id = {1, 2};
    jam::Species<2> species(ratio);
    jam::System<2> sys(p, species, jam::CompressingBox<2>{10.0, 0.0, 1.0}, 0.3);
    sys.compute_elastic_forces(10.0);
    const double expected = 2.0 / (ratio * ratio) / (ratio * ratio);
    BOOST_TEST(jam::stiffest_mode(sys, 10.0, species.drag) == expected,
               boost::test_tools::tolerance(1e-12));
  }
}

BOOST_AUTO_TEST_CASE(jam_sim_across_the_range) {
  const fs::path dir = fs::temp_directory_path() / ("jam-ratio-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "r.h5").string();
  auto jam = [&](const std::string& ratio) {
    return jam::test::run_jam_logged(dir / "log.txt",
                                     "sim --quiet --n 128 --rate 1e-2 --phi-step 0.005 "
                                     "--phi-init 0.7 --phi-stop 0.9 --out " +
                                         out + " --diameter-ratio " + ratio)
        .status;
  };
  for (const char* ratio : {"1.0", "2.0"}) {
    BOOST_TEST_REQUIRE(jam(ratio) == 0);
    const auto f = jam::h5::File::open_read(out);
    BOOST_TEST(f.read_attribute_double("diameter_ratio") == std::atof(ratio));
    const auto p = f.read_dataset("pressure");
    BOOST_TEST(std::all_of(p.begin(), p.end(), [](double x) { return std::isfinite(x); }));
    BOOST_TEST(p.back() > 0.0);  // phi 0.9 is above jamming for any ratio in 2D
  }
  for (const char* ratio : {"0.99", "2.01", "nan", "-1"}) {
    fs::remove(out);
    BOOST_TEST(jam(ratio) != 0);
    BOOST_TEST(!fs::exists(out));
  }
  fs::remove_all(dir);
}
