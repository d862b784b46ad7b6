// Long runs: nothing accumulates. The box is L0 exp(-rate k dt), recomputed from the step
// count k at every step, so phi(t) stays exact to round-off over the paper's longest runs
// (rate 10^-8.5 from phi 0.40 to 0.88 in 2D: 1.25e9 steps at the campaign's dt 0.1). The
// bookkeeping has no state, so it is fast-forwarded: checked at 1e6 step counts spread over the
// whole run (phi from the formula and from the box length at each) against a long-double
// reference. Then 1e7 real steps of a small system: positions stay wrapped, phi
// stays exact, and the neighbor list is rebuilt as often as the affine shrinking requires.
// Sizes: N = 2 runs where the box allows it.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "campaign/campaign_file.hpp"
#include "helpers.hpp"
#include "process.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/io/hdf5_file.hpp"

namespace fs = std::filesystem;

namespace {

/// Largest relative error of phi(k dt) (the formula and V_p / L(k dt)^D, both as the simulator
/// computes them) against phi0 exp(D rate k dt) in long double, over k in [0, steps].
template <int D>
double worst_packing_error(double phi0, double rate, double dt, double steps) {
  jam::CompressingBox<D> box;
  box.initial_length = 7.3;
  box.particle_volume = phi0 * std::pow(box.initial_length, D);
  box.compression_rate = rate;
  const long double phi_start = static_cast<long double>(box.packing_fraction(0.0));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, steps);
  double worst = 0.0;
  for (int sample = 0; sample < 1000000; ++sample) {
    const double k = sample == 0 ? steps : std::floor(u(rng));
    const double t = k * dt;
    const long double expected =
        phi_start * std::exp(static_cast<long double>(D) * rate * static_cast<long double>(k) * dt);
    const double from_formula = box.packing_fraction(t);
    const double from_length = box.particle_volume / std::pow(box.length(t), D);
    for (double phi : {from_formula, from_length}) {
      worst = std::max(worst, static_cast<double>(std::abs(phi - expected) / expected));
    }
  }
  return worst;
}

}  // namespace

// Relative error bound 1e-14: exp, pow and the products each add a few ulp (1.1e-16) and the
// time t = k dt is rounded once (relative 1e-16, times D rate t <= 0.8), so a few 1e-16 is
// expected. Growing a box length step by step (L *= exp(-rate dt)) would instead drift by
// about k ulp, ~1e-6 after 1e10 steps, and fail.
BOOST_AUTO_TEST_CASE(packing_fraction_over_the_longest_paper_runs) {
  for (const char* name : {"paper-2d.toml", "paper-3d.toml"}) {
    const jam::Campaign c = jam::read_campaign(
        (std::filesystem::path(JAM_SOURCE_DIR) / "reference" / "campaigns" / name).string());
    const double slowest =
        std::pow(10.0, *std::min_element(c.log10_rates.begin(), c.log10_rates.end()));
    const double phi0 = *std::min_element(c.phi_init.begin(), c.phi_init.end());
    const double steps =
        std::ceil(std::log(c.run.phi_stop / phi0) / (c.run.dim * slowest * c.run.dt));
    BOOST_TEST(steps >= 1e7);
    const double worst = c.run.dim == 2 ? worst_packing_error<2>(phi0, slowest, c.run.dt, steps)
                                        : worst_packing_error<3>(phi0, slowest, c.run.dt, steps);
    BOOST_TEST_MESSAGE(name << ": rate " << slowest << ", " << steps
                            << " steps, max |phi - phi_expected| / phi = " << worst);
    BOOST_TEST(worst < 1e-14);
  }
}

// 1e7 steps of 8 particles in 2D from phi 0.05 to 0.5 (rate 1.15e-5, dt 0.01). Positions stay
// in [0, 1) at every step; phi at the end is exact to round-off; the list is rebuilt at least as
// often as the affine shrinking alone requires (lambda = L/L_build must stay above
// d_max / (d_max + skin)) and not much more (particles barely touch at these packings).
BOOST_AUTO_TEST_CASE(ten_million_steps) {
  const double dt = 0.01, phi0 = 0.05, phi1 = 0.5;
  const long long steps = 10000000;
  const double rate = std::log(phi1 / phi0) / (2.0 * steps * dt);
  auto sys = jam::test::random_system<2>(8, phi0, 3, rate);
  jam::OverdampedEuler<2> stepper(sys.size());
  bool wrapped = true;
  for (long long k = 0; k < steps; ++k) {
    stepper.step(sys, static_cast<double>(k) * dt, dt);
    for (int d = 0; d < 2; ++d)
      for (double s : sys.particles.s[d]) wrapped = wrapped && s >= 0.0 && s < 1.0;
  }
  BOOST_TEST(wrapped);
  const double phi_end = sys.box.packing_fraction(static_cast<double>(steps) * dt);
  BOOST_TEST(std::abs(phi_end - phi1) / phi1 < 1e-13);  // rate itself rounded; see above
  const double d_max = sys.species.max_contact_distance, skin = sys.neighbors.skin();
  const double affine_builds =
      std::ceil(std::log(phi1 / phi0) / 2.0 / std::log((d_max + skin) / d_max));
  BOOST_TEST_MESSAGE("1e7 steps: " << sys.neighbors.builds() << " neighbor-list builds, "
                                   << affine_builds << " required by the shrinking box alone");
  BOOST_TEST(sys.neighbors.builds() >= affine_builds);
  BOOST_TEST(sys.neighbors.builds() <= 20 * affine_builds);
}

// N = 2 runs wherever the box is larger than twice the interaction range (d_max + skin = 1.7):
// in 2D up to phi = 2 (pi/4)(1 + 1.96) / 3.4^2 = 0.201, in 3D up to 0.0499. Beyond, an error.
BOOST_AUTO_TEST_CASE(two_particles) {
  const fs::path dir = fs::temp_directory_path() / ("jam-long-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "two.h5").string();
  const fs::path log = dir / "log.txt";
  auto jam = [&](const std::string& args) {
    return jam::test::run_jam_logged(log, "sim --quiet --n 2 --out " + out + " " + args).status;
  };
  BOOST_TEST(jam("--phi-init 0.1 --phi-stop 0.2 --rate 1e-2") == 0);
  BOOST_TEST(jam::h5::File::open_read(out).read_dataset("pressure").size() > 50u);
  BOOST_TEST(jam("--dim 3 --phi-init 0.02 --phi-stop 0.049 --rate 1e-2") == 0);
  fs::remove(out);
  BOOST_TEST(jam("--phi-init 0.1 --phi-stop 0.21") != 0);
  BOOST_TEST(!fs::exists(out));
  fs::remove_all(dir);
}
