// The inertial integrator follows LAMMPS (fix nve + fix viscous + fix deform trate remap x,
// reference/lammps/compress_inertial.in) step by step, and the default overdamped dynamics
// matches LAMMPS at Q = 0.03 through jamming: `jam check lammps` with LAMMPS run now (not the
// stored result) passes in 2D and 3D - positions to 1e-9 after 400 steps (measured ~7e-12),
// pressure and energy to 1e-5 relative, contacts exactly, overdamped pressure within 0.5%. The
// tolerances are argued in checks/lammps_check.cpp; a step-order mistake (forces at the deformed
// box) moves particles by ~5e-6 and fails.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>

#include "checks/lammps_check.hpp"
#include "sim/io/process.hpp"
#include "sim/model/contact_laws.hpp"

namespace fs = std::filesystem;

BOOST_AUTO_TEST_CASE(inertial_dynamics_follows_lammps_run_now) {
  BOOST_TEST_REQUIRE(!jam::find_program("lmp").empty(),
                     "LAMMPS (lmp) is needed: scripts/setup.sh installs it");
  const fs::path dir = fs::temp_directory_path() / ("jam-lammps-" + std::to_string(::getpid()));
  jam::checks::LammpsCheckOptions o;
  o.work_directory = dir.string();
  o.reference_directory = (fs::path(JAM_SOURCE_DIR) / "reference" / "lammps").string();
  o.use_lmp = true;
  const auto verdicts = jam::checks::lammps_check(o);
  // positions, pressure, energy, contacts in 2D and 3D for every contact law, then the
  // overdamped comparison at small Q in 2D and 3D
  BOOST_TEST(verdicts.size() == 8u * std::tuple_size_v<jam::ContactLaws> + 2u);
  for (const auto& v : verdicts) {
    BOOST_TEST_MESSAGE(v.case_name << ": " << v.statistic);
    BOOST_TEST(v.status == "pass", v.case_name << ": " << v.reason);
    BOOST_TEST(v.reason.find("LAMMPS run now") != std::string::npos, v.reason);
  }
  fs::remove_all(dir);
}
