// Random starts far above jamming (phi_init 0.92 in 2D, 0.72 in 3D: heavy overlaps everywhere)
// with two pairs of particles placed at exactly the same point (one pair of equal species, one
// mixed) relax and compress without a single non-finite number, under every integrator, and
// through the whole `jam sim` pipeline (data file in, run file out).
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "helpers.hpp"
#include "process.hpp"
#include "sim/dynamics/inertial_verlet.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/observables/observables.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-extreme-" + std::to_string(::getpid()));

/// A random start at phi with two particles moved onto particle 0: one of its species, one of
/// the other.
template <int D>
jam::System<D> coincident_start(std::size_t n, double phi, std::uint64_t seed, double rate) {
  jam::System<D> sys = jam::test::random_system<D>(n, phi, seed, rate);
  auto& p = sys.particles;
  std::size_t small_partner = 0, big_partner = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (p.type[i] == p.type[0] && small_partner == 0) small_partner = i;
    if (p.type[i] != p.type[0] && big_partner == 0) big_partner = i;
  }
  BOOST_REQUIRE(small_partner > 0 && big_partner > 0);
  for (int d = 0; d < D; ++d) {
    p.s[d][small_partner] = p.s[d][0];
    p.s[d][big_partner] = p.s[d][0];
  }
  return sys;
}

template <int D>
void require_finite(const jam::System<D>& sys, double t, const char* where) {
  bool finite = true;
  for (int d = 0; d < D; ++d) {
    for (std::size_t i = 0; i < sys.size(); ++i) {
      finite = finite && std::isfinite(sys.particles.s[d][i]) && std::isfinite(sys.force[d][i]);
    }
  }
  BOOST_REQUIRE_MESSAGE(finite, where << ": non-finite position or force at t = " << t);
}

template <int D, class Stepper>
void relax_and_compress(jam::System<D>& sys, Stepper& stepper, double dt, int steps) {
  const double rate = sys.box.compression_rate;
  sys.box.compression_rate = 0.0;  // relaxation at zero rate first, as a run does
  for (int k = 0; k < steps; ++k) {
    stepper.step(sys, k * dt, dt);
    require_finite(sys, k * dt, "relaxation");
  }
  sys.box.compression_rate = rate;
  stepper.reset();
  for (int k = 0; k < steps; ++k) {
    stepper.step(sys, k * dt, dt);
    require_finite(sys, k * dt, "compression");
  }
  const auto obs = jam::measure(sys, steps * dt, true);
  BOOST_TEST(std::isfinite(obs.pressure));
  BOOST_TEST(obs.pressure > 0.0);
  BOOST_TEST(std::isfinite(obs.energy_per_particle));
  BOOST_TEST(std::isfinite(obs.contacts_per_particle_no_rattlers));
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) BOOST_TEST(std::isfinite(obs.stress[a][b]));
}

template <int D>
void all_integrators(double phi) {
  const double dt = 0.01, rate = 1e-3;
  const int steps = 1500;
  {
    auto sys = coincident_start<D>(512, phi, 11, rate);
    jam::OverdampedEuler<D> stepper(sys.size());
    relax_and_compress(sys, stepper, dt, steps);
  }
  {
    auto sys = coincident_start<D>(512, phi, 12, rate);
    jam::OverdampedHeun<D> stepper(sys.size());
    relax_and_compress(sys, stepper, dt, steps);
  }
  {
    auto sys = coincident_start<D>(512, phi, 13, rate);
    jam::InertialVerlet<D> stepper(sys.size(), 0.1);  // dt = 0.01 < 4 Q^2 / D = 0.013 (3D)
    relax_and_compress(sys, stepper, 0.005, steps);
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(integrators_2d_phi_092) {
  all_integrators<2>(0.92);
}

BOOST_AUTO_TEST_CASE(integrators_3d_phi_072) {
  all_integrators<3>(0.72);
}

// The same starts through `jam sim`: read from a data file, relaxed (for 20 t0: above jamming
// the energy has no zero to relax to), compressed further; the run file has only finite numbers.
template <int D>
void through_jam_sim(double phi, double phi_stop) {
  fs::create_directories(kDir);
  auto sys = coincident_start<D>(256, phi, 21, 0.0);
  const fs::path data = kDir / ("start" + std::to_string(D) + ".data");
  const fs::path out = kDir / ("run" + std::to_string(D) + ".h5");
  jam::write_lammps_data(data.string(), sys.particles, sys.box.initial_length, 1.0, 1.0,
                         "coincident start");
  const std::string args = "sim --dim " + std::to_string(D) + " --read-lammps-data " +
                           data.string() + " --phi-stop " + std::to_string(phi_stop) +
                           " --rate 1e-3 --relax-time-max 20 --quiet --rattlers --stress --out " +
                           out.string();
  BOOST_REQUIRE_EQUAL(jam::test::run_jam_logged(kDir / "log.txt", args).status, 0);
  const auto f = jam::h5::File::open_read(out.string());
  for (const char* name : {"pressure", "energy_per_particle", "contacts_per_particle",
                           "contacts_per_particle_no_rattlers", "packing_fraction"}) {
    const auto v = f.read_dataset(name);
    BOOST_TEST(!v.empty());
    for (double x : v) BOOST_TEST(std::isfinite(x), name);
  }
}

BOOST_AUTO_TEST_CASE(jam_sim_2d_and_3d) {
  through_jam_sim<2>(0.92, 0.95);
  through_jam_sim<3>(0.72, 0.75);
}
