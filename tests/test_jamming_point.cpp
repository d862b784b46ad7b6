// FIRE minimization and the jamming point phi_Ji: FIRE removes every overlap below jamming
// and balances the forces above it; a perfect square (cubic) lattice of equal spheres
// compressed through contact jams exactly at phi = pi/4 (pi/6), which the run finds. A search
// stopped and resumed replays its decisions and gives the uninterrupted search's point.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "helpers.hpp"
#include "sim/dynamics/fire_minimizer.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/observables/jamming_point.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/compression_run.hpp"

using namespace jam;
namespace fs = std::filesystem;

BOOST_AUTO_TEST_CASE(fire_relaxes_below_and_balances_above_jamming) {
  System<2> loose = test::random_system<2>(256, 0.60, 1);
  const double l1 = loose.box.length(0.0);
  const FireResult r1 = minimize_fire(loose, l1);
  BOOST_TEST(r1.converged);
  // Overlaps left are below the force tolerance: energy ~ f_tol^2 per contact.
  BOOST_TEST(measure(loose, 0.0, false).energy_per_particle < 1e-20);
  BOOST_TEST(measure(loose, 0.0, false).pressure < 1e-8);  // below the jammed threshold

  System<2> dense = test::random_system<2>(256, 0.90, 2);
  const double l2 = dense.box.length(0.0);
  const FireResult r2 = minimize_fire(dense, l2);
  BOOST_TEST(r2.converged);
  BOOST_TEST(r2.max_force < 1e-10);
  const auto obs = measure(dense, 0.0, false);
  BOOST_TEST(obs.pressure > 1e-3);  // jammed: a finite pressure survives
  BOOST_TEST(obs.contacts_per_particle > 3.5);
}

namespace {

// Compresses a lattice of m^D equal small spheres (spacing a0 > 1) through contact and returns
// the run's phi_Ji.
template <int D>
double lattice_jamming_point(int m, double a0, double phi_stop, double search_from) {
  const fs::path dir =
      fs::temp_directory_path() / ("jam-jp-" + std::to_string(::getpid()) + std::to_string(D));
  fs::create_directories(dir);
  ParticleData<D> p;
  const int sites = static_cast<int>(std::pow(m, D));
  p.resize(static_cast<std::size_t>(sites));
  for (int k = 0; k < sites; ++k) {
    int rest = k;
    for (int d = 0; d < D; ++d) {
      p.s[d][static_cast<std::size_t>(k)] = (rest % m + 0.5) / m;
      rest /= m;
    }
    p.type[static_cast<std::size_t>(k)] = 0;
    p.id[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(k + 1);
  }
  write_lammps_data<D>((dir / "lattice.data").string(), p, m * a0, 1.0, 1.0, "lattice");
  SimConfig c;
  c.dim = D;
  c.read_lammps_data = (dir / "lattice.data").string();
  c.n_given = c.phi_init_given = false;
  c.phi_stop = phi_stop;
  c.phi_step = 0.002;
  c.compression_rate = 1e-3;
  c.relax = false;
  c.jamming_point = true;
  c.jamming_search_from = search_from;
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.out = (dir / "run.h5").string();
  run_compression(c);
  const double phi_j = h5::File::open_read(c.out).read_attribute_double("jamming_packing_fraction");
  fs::remove_all(dir);
  return phi_j;
}

}  // namespace

BOOST_AUTO_TEST_CASE(square_and_cubic_lattices_jam_at_contact) {
  // Resolution of the refinement is 1e-5; the pressure threshold moves the point by < 1e-7.
  BOOST_TEST(std::abs(lattice_jamming_point<2>(8, 1.06, 0.80, 0.75) - std::numbers::pi / 4) < 2e-5);
  BOOST_TEST(std::abs(lattice_jamming_point<3>(5, 1.05, 0.54, 0.50) - std::numbers::pi / 6) < 2e-5);
}

BOOST_AUTO_TEST_CASE(a_resumed_search_replays_its_decisions) {
  // One random bidisperse configuration (N = 128) at packings 0.78 ... 0.90, scaled positions
  // fixed: it jams somewhere between (random packings near 0.84).
  System<2> sys = test::random_system<2>(128, 0.80, 7);
  std::vector<double> s;
  for (int d = 0; d < 2; ++d)
    s.insert(s.end(), sys.particles.s[d].begin(), sys.particles.s[d].end());
  std::vector<SavedConfiguration> saved;
  for (int k = 0; k <= 12; ++k) saved.push_back({0.78 + 0.01 * k, s});

  // The search releases the configurations its bracket leaves: the checkpoint taken after
  // each decision (here: a copy of what the search still holds) shrinks with it.
  const std::size_t half_way = 6;  // 2 ends, then 3-4 bisections bring 13 down to 2
  JammingAnswers answers;
  std::vector<SavedConfiguration> work = saved, checkpointed;
  const JammingPoint full = find_jamming_point(sys, work, nullptr, &answers, [&] {
    if (answers.size() == half_way) checkpointed = work;
  });
  BOOST_TEST_REQUIRE(full.bracketed);
  BOOST_TEST(full.replayed == 0);
  BOOST_TEST(answers.size() == static_cast<std::size_t>(full.minimizations));
  BOOST_TEST(full.minimizations > 8);  // 2 ends, ~4 bisections over 13, ~10 refinements
  const auto kept = [](const std::vector<SavedConfiguration>& v) {
    std::vector<double> phi;
    for (const auto& c : v)
      if (!c.s.empty()) phi.push_back(c.packing_fraction);
    return phi;
  };
  const auto bracket = kept(work);  // the two ends the refinement interpolated between
  BOOST_TEST_REQUIRE(bracket.size() == 2u);
  BOOST_TEST(std::abs(bracket[1] - bracket[0] - 0.01) < 1e-12);
  BOOST_TEST(bracket[0] < full.packing_fraction);
  BOOST_TEST(full.packing_fraction < bracket[1]);
  BOOST_TEST_REQUIRE(checkpointed.size() == saved.size());
  BOOST_TEST(kept(checkpointed).size() == 2u);

  // Stopped after those decisions: the resumed search, from the configurations it had kept,
  // minimizes only the rest and lands on the same point bit for bit (the same minimizations
  // from the same configurations).
  JammingAnswers half(answers.begin(), answers.begin() + half_way);
  const JammingPoint resumed = find_jamming_point(sys, checkpointed, nullptr, &half);
  BOOST_TEST(resumed.replayed == static_cast<int>(half_way));
  BOOST_TEST(resumed.minimizations == full.minimizations);
  BOOST_TEST(resumed.packing_fraction == full.packing_fraction);
  BOOST_TEST((half == answers));

  // The replayed decisions steer the search: one flipped (the first bisection's) leads it to
  // another bracket, so a replay that ignored them would go unnoticed no more.
  JammingAnswers flipped(answers.begin(), answers.begin() + 3);
  flipped[2] = 1 - flipped[2];
  std::vector<SavedConfiguration> all = saved;
  const JammingPoint misled = find_jamming_point(sys, all, nullptr, &flipped);
  BOOST_TEST(misled.replayed == 3);
  BOOST_TEST(std::abs(misled.packing_fraction - full.packing_fraction) > 1e-3);

  // Answers that lead outside what was kept (a checkpoint that contradicts itself) are an
  // error, not a minimization of an empty configuration.
  std::vector<SavedConfiguration> pruned = work;
  JammingAnswers misleading(answers.begin(), answers.begin() + 3);
  misleading[2] = 1 - misleading[2];
  BOOST_CHECK_EXCEPTION(find_jamming_point(sys, pruned, nullptr, &misleading), std::runtime_error,
                        [](const std::runtime_error& e) {
                          return std::string(e.what()).find("was not kept") != std::string::npos;
                        });
}
