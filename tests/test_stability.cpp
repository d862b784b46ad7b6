// Time steps beyond the stability bound of the integrator are refused with one line naming --dt
// and the estimated safe bound, a non-zero exit and no run file; time steps inside the bound
// run. 2D and 3D, Euler and Heun, and velocity Verlet at a large quality factor. Also: the
// stability estimate itself against a case with a closed form.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "helpers.hpp"
#include "process.hpp"
#include "sim/dynamics/stability.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/model/hertzian_contact.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-stability-" + std::to_string(::getpid()));

struct Outcome {
  int status;
  std::string err;
};

Outcome run_sim(const std::string& args, const fs::path& out) {
  fs::create_directories(kDir);
  fs::remove(out);
  // --phi-step 0.05: output sparse enough that the steps tried here stay within one interval.
  const auto o = jam::test::run_jam_stderr(
      kDir / "stderr.txt",
      "sim " + args + " --quiet --checkpoint-interval 0 --phi-step 0.05 --out " + out.string());
  return {o.status, o.output};
}

/// The safe bound the error message states ("... = 0.353 (estimated safe bound").
double stated_bound(const std::string& err) {
  const auto end = err.find(" (estimated safe bound");
  BOOST_REQUIRE(end != std::string::npos);
  const auto begin = err.rfind("= ", end);
  return std::stod(err.substr(begin + 2, end - begin - 2));
}

void expect_refused(const Outcome& o, const fs::path& out, const std::string& dt_text) {
  BOOST_TEST(o.status != 0);
  BOOST_TEST(o.err.find("--dt " + dt_text + ": unstable") != std::string::npos, o.err);
  BOOST_TEST(o.err.find("estimated safe bound") != std::string::npos, o.err);
  BOOST_TEST(std::count(o.err.begin(), o.err.end(), '\n') == 1);
  BOOST_TEST(!fs::exists(out));
  for (const auto& e : fs::directory_iterator(out.parent_path())) {
    BOOST_TEST(e.path().string().find(".partial") == std::string::npos, e.path());
  }
}

std::string g(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

// Two small particles overlapping along x: the relative coordinate relaxes at rate
// lambda = k (1/gamma_s + 1/gamma_s) = 2 k / gamma_s with k = 1/d^2 = 1 and gamma_s = 2/D, so
// lambda = D. The Gershgorin bound is exact here too (one contact, equal particles).
BOOST_AUTO_TEST_CASE(two_particle_rate) {
  {
    auto sys = jam::test::make_system<2>({{{0.0, 0.0}}, {{0.9, 0.0}}}, {0, 0}, 10.0);
    sys.compute_elastic_forces(10.0);
    BOOST_TEST(jam::stiffest_mode(sys, 10.0, sys.species.drag) == 2.0,
               boost::test_tools::tolerance(1e-12));
    BOOST_TEST(jam::stiffest_mode_bound(sys, 10.0, sys.species.drag) == 2.0,
               boost::test_tools::tolerance(1e-12));
  }
  {
    auto sys = jam::test::make_system<3>({{{0.0, 0.0, 0.0}}, {{0.5, 0.5, 0.0}}}, {0, 0}, 10.0);
    sys.compute_elastic_forces(10.0);
    BOOST_TEST(jam::stiffest_mode(sys, 10.0, sys.species.drag) == 3.0,
               boost::test_tools::tolerance(1e-12));
  }
  {  // two particles at the same point: no direction, no radial stiffness, finite answer
    auto sys = jam::test::make_system<2>({{{0.0, 0.0}}, {{0.0, 0.0}}}, {0, 1}, 10.0);
    sys.compute_elastic_forces(10.0);
    BOOST_TEST(std::isfinite(jam::stiffest_mode(sys, 10.0, sys.species.drag)));
  }
}

// The same pair with the Hertzian law: k = U'' = (3/2) delta^(1/2) / d^2 depends on the
// overlap delta = 1 - r/d, so lambda = 2 k / gamma_s = D (3/2) delta^(1/2) (d = 1).
BOOST_AUTO_TEST_CASE(two_particle_rate_hertzian) {
  for (double r : {0.9, 0.99, 0.5}) {
    auto sys =
        jam::test::make_system<2, jam::HertzianContact>({{{0.0, 0.0}}, {{r, 0.0}}}, {0, 0}, 10.0);
    sys.compute_elastic_forces(10.0);
    const double lambda = 2.0 * 1.5 * std::sqrt(1.0 - r);
    BOOST_TEST(jam::stiffest_mode(sys, 10.0, sys.species.drag) == lambda,
               boost::test_tools::tolerance(1e-12));
    BOOST_TEST(jam::stiffest_mode_bound(sys, 10.0, sys.species.drag) == lambda,
               boost::test_tools::tolerance(1e-12));
  }
}

// A random start relaxed at zero rate and compressed: the stiffest mode of the random start
// (before any step, so independent of dt) sets the bound. dt = 1 and 1.1 x the stated bound are
// refused at once; 0.9 x the bound runs through jamming (2D to phi 0.86, 3D to 0.68), where the
// contact network is softer than the random start (measured: lambda_max 4.9 at phi 0.86 in 2D
// against 5.4 at the start; 7.5 at 0.68 in 3D against 10.5).
BOOST_AUTO_TEST_CASE(overdamped_bound_2d_and_3d) {
  for (int dim : {2, 3}) {
    for (const std::string integrator : {"euler", "heun"}) {
      BOOST_TEST_CONTEXT(dim << "D " << integrator) {
        const std::string base =
            "--dim " + std::to_string(dim) + " --n 256 --integrator " + integrator +
            " --rate 1e-3 --seed 3" +
            (dim == 2 ? " --phi-init 0.6 --phi-stop 0.86" : " --phi-init 0.5 --phi-stop 0.68");
        const fs::path out = kDir / "run.h5";
        const Outcome far = run_sim(base + " --dt 1", out);
        expect_refused(far, out, "1");
        const double bound = stated_bound(far.err);
        BOOST_TEST(bound > 0.05);
        BOOST_TEST(bound < 1.0);
        const std::string above = g(1.1 * bound);
        expect_refused(run_sim(base + " --dt " + above, out), out, above);
        const Outcome inside = run_sim(base + " --dt " + g(0.9 * bound), out);
        BOOST_TEST(inside.status == 0, inside.err);
        BOOST_TEST(fs::exists(out));
      }
    }
  }
}

template <int D>
double stiffest_of_file(const fs::path& file) {
  auto data = jam::read_lammps_data<D>(file.string());
  jam::Species<D> species;
  jam::CompressingBox<D> box{data.box_length, 0.0,
                             jam::total_particle_volume(data.particles, species)};
  jam::System<D> sys(std::move(data.particles), species, box, 0.3);
  sys.compute_elastic_forces(data.box_length);
  return jam::stiffest_mode(sys, data.box_length, species.drag, 300);
}

// A relaxed start below jamming is softer than the packing it is compressed into (in 3D,
// measured lambda_max 5.3 at phi 0.45 against 7.3 at 0.68; in 2D 4.3 at 0.6 against 4.9 at
// 0.9: any contact has stiffness 1/d^2 however small its overlap, so a relaxed start is not
// contact-free). A dt between 1.9/lambda_max of the two passes the start and must be stopped
// during the compression, leaving no run file.
BOOST_AUTO_TEST_CASE(instability_that_appears_during_compression) {
  for (int dim : {2, 3}) {
    BOOST_TEST_CONTEXT(dim << "D") {
      const fs::path start = kDir / ("start" + std::to_string(dim) + ".data");
      const fs::path end = kDir / ("end" + std::to_string(dim) + ".data");
      const fs::path out = kDir / "run.h5";
      const std::string d = " --dim " + std::to_string(dim);
      const std::string phi_stop = dim == 2 ? "0.9" : "0.72";
      const Outcome made =
          run_sim(d + " --n 256 --rate 1e-3 --seed 4 --phi-stop 0.7 --phi-init " +
                      (dim == 2 ? "0.6" : "0.45") + " --write-lammps-data " + start.string(),
                  out);
      BOOST_REQUIRE(made.status == 0);
      const Outcome reference =
          run_sim(d + " --read-lammps-data " + start.string() + " --relax 0 --rate 1e-3 " +
                      "--phi-stop " + phi_stop + " --write-final-lammps-data " + end.string(),
                  out);
      BOOST_REQUIRE(reference.status == 0);
      const double soft = dim == 2 ? stiffest_of_file<2>(start) : stiffest_of_file<3>(start);
      const double stiff = dim == 2 ? stiffest_of_file<2>(end) : stiffest_of_file<3>(end);
      BOOST_TEST_MESSAGE(dim << "D lambda_max: start " << soft << ", at phi " << phi_stop << " "
                             << stiff);
      BOOST_REQUIRE(stiff > 1.08 * soft);
      const std::string dt = g(1.9 / std::sqrt(soft * stiff));
      const Outcome o = run_sim(d + " --read-lammps-data " + start.string() +
                                    " --relax 0 --rate 1e-4 --integrator heun --dt " + dt +
                                    " --phi-stop " + phi_stop,
                                out);
      expect_refused(o, out, dt);
      BOOST_TEST(o.err.find("(compression at phi") != std::string::npos, o.err);
    }
  }
}

// Inertial dynamics at Q = 1: the drag bound dt < 4 Q^2 / D = 2 (2D) allows dt = 1, but the
// stiffest contact oscillates at omega_max > 1.9 / 1, which velocity Verlet cannot follow.
BOOST_AUTO_TEST_CASE(inertial_contact_frequency) {
  const fs::path out = kDir / "run.h5";
  const std::string base = "--dim 2 --n 256 --dynamics inertial --q 1 --rate 1e-3 --seed 5";
  const Outcome o = run_sim(base + " --dt 1", out);
  expect_refused(o, out, "1");
  BOOST_TEST(o.err.find("omega_max") != std::string::npos, o.err);
  const Outcome inside = run_sim(base + " --dt " + g(0.9 * stated_bound(o.err)), out);
  BOOST_TEST(inside.status == 0, inside.err);
}
