// What a LAMMPS log must show before its packing may follow from the time: hand-written logs
// of a 2D run of 64 atoms at trate -1e-3 from phi 0.8. One run under one isotropic deform (its
// echoes after each substitution are one command) imports, phi = 0.8 exp(2 rate t); a
// relaxation run after the compression, a rate changed between runs and a deform of x alone
// are refused with one line naming the log and the line, and nothing is written. A deform of x
// alone is refused whichever column gives the packing (the model is an isotropic compression);
// the bundled input's route (--data) refuses a second run as well.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"
#include "sim/io/lammps_import.hpp"
#include "sim/io/lammps_log.hpp"
#include "sim/io/open_run.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("jam_test_lammps_log_protocol_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Lines 1-4 of every log; the deform (when there is one) follows from line 5.
const std::string kHead =
    "LAMMPS (29 Sep 2021 - Update 2)\n"
    "dimension 2\n"
    "Created 64 atoms\n"
    "timestep 0.01\n";

// As LAMMPS echoes a deform given through a variable: as written, then once per substitution.
const std::string kDeform =
    "fix compress all deform 1 x trate ${minus_rate} y trate ${minus_rate} remap x\n"
    "fix compress all deform 1 x trate -0.001 y trate ${minus_rate} remap x\n"
    "fix compress all deform 1 x trate -0.001 y trate -0.001 remap x\n";

/// A run of `steps` steps from `step0`: its header and a row every 100 steps.
std::string run_block(int step0, int steps, double pressure) {
  std::string out = "run " + std::to_string(steps) + "\nStep Time c_virial Volume\n";
  for (int s = step0; s <= step0 + steps; s += 100) {
    const double t = 0.01 * s;
    // the box of 64 atoms at phi 0.8 shrinking at 1e-3 (only the volume route reads it)
    const double volume = 32 * (M_PI / 4) * (1 + 1.96) / (0.8 * std::exp(2e-3 * t));
    out += std::to_string(s) + " " + std::to_string(t) + " " + std::to_string(pressure) + " " +
           std::to_string(volume) + "\n";
  }
  return out + "Loop time of 0.1 on 1 procs for " + std::to_string(steps) +
         " steps with 64 atoms\n";
}

struct Log {
  fs::path dir, path;
};

Log write_log(const std::string& name, const std::string& text) {
  Log l{scratch(name), {}};
  l.path = l.dir / "log.lammps";
  std::ofstream(l.path) << text;
  return l;
}

/// The time-only route: pressure and time named, --phi-init 0.8.
jam::LammpsImport from_time(const Log& l) {
  jam::LammpsImport r;
  r.log = l.path.string();
  r.out = (l.dir / "run.h5").string();
  r.columns = {{"pressure", "c_virial"}, {"time", "Time"}};
  r.phi_init = 0.8;
  r.diameter_ratio = 1.4;
  r.sample = 0;
  return r;
}

/// The import fails with one line holding every one of `parts`, and writes nothing.
void refused(const jam::LammpsImport& r, const std::vector<std::string>& parts) {
  try {
    jam::import_lammps_log(r);
    BOOST_FAIL("imported " + r.log);
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    BOOST_TEST(what.find('\n') == std::string::npos, what);
    for (const auto& p : parts) BOOST_TEST(what.find(p) != std::string::npos, what);
  }
  BOOST_TEST(!fs::exists(r.out));
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_run_under_one_isotropic_deform_imports_from_the_time) {
  const Log l = write_log("one_run", kHead + kDeform + run_block(0, 200, 0.001));
  const jam::LammpsLog log = jam::read_lammps_log(l.path.string(), {"c_virial", "Time"});
  BOOST_TEST(log.deforms.size() == 1u);  // the three echoes are one command
  BOOST_TEST(log.deforms[0].line == 7);
  BOOST_TEST(log.runs == std::vector<int>{9}, boost::test_tools::per_element());
  jam::import_lammps_log(from_time(l));
  const jam::OpenRun run = jam::read_open_run((l.dir / "run.h5").string());
  BOOST_TEST(run.compression_rate == 1e-3);
  BOOST_REQUIRE(run.packing_fraction.size() == 3u);
  BOOST_TEST(run.packing_fraction.back() == 0.8 * std::exp(2 * 1e-3 * 2.0),
             boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(a_relaxation_run_after_the_compression_is_refused_from_the_time) {
  // Lines 5-7 the deform, 8 "run", 9 the first header, 10-12 rows, 13 Loop, 14 unfix,
  // 15 "run", 16 the second header.
  const Log l = write_log("relaxation", kHead + kDeform + run_block(0, 200, 0.001) +
                                            "unfix compress\n" + run_block(200, 200, 0.0005));
  refused(from_time(l),
          {l.path.string() + ":16: a second run (the first at line 9)", "--column volume=Volume"});
  // Steps instead of times: the same route, the same refusal.
  jam::LammpsImport steps = from_time(l);
  steps.columns = {{"pressure", "c_virial"}, {"step", "Step"}};
  refused(steps, {l.path.string() + ":16: a second run"});
}

BOOST_AUTO_TEST_CASE(a_rate_changed_between_runs_is_refused) {
  // The second deform (line 14) replaces the first at 1e-4 for the second run.
  const Log l = write_log(
      "rate_change", kHead + kDeform + run_block(0, 200, 0.001) +
                         "fix compress all deform 1 x trate -0.0001 y trate -0.0001 remap x\n" +
                         run_block(200, 200, 0.002));
  refused(from_time(l),
          {l.path.string() + ":14: fix compress deform: trate -0.0001", "line 7 has trate -0.001"});
  // With a volume column too: a run of the model has one rate.
  jam::LammpsImport volume = from_time(l);
  volume.columns["volume"] = "Volume";
  volume.phi_init.reset();
  refused(volume, {l.path.string() + ":14:"});
}

BOOST_AUTO_TEST_CASE(a_deform_of_x_alone_is_refused_by_every_route) {
  const Log l = write_log("x_only", kHead + "fix compress all deform 1 x trate -0.001 remap x\n" +
                                        run_block(0, 200, 0.001));
  refused(from_time(l), {l.path.string() + ":5: fix compress deform: x trate -0.001, y not "
                                           "deformed: not an isotropic compression"});
  jam::LammpsImport volume = from_time(l);
  volume.columns = {{"pressure", "c_virial"}, {"volume", "Volume"}};
  volume.phi_init.reset();
  refused(volume, {l.path.string() + ":5:", "not an isotropic compression"});
  // Each axis at its own rate is no isotropic compression either.
  const Log both = write_log(
      "x_y_apart", kHead + "fix compress all deform 1 x trate -0.001 y trate -0.002 remap x\n" +
                       run_block(0, 200, 0.001));
  refused(from_time(both), {both.path.string() + ":5:", "not an isotropic compression"});
}

BOOST_AUTO_TEST_CASE(the_time_route_needs_the_logs_own_deform_before_its_rows) {
  const Log none = write_log("no_deform", kHead + run_block(0, 200, 0.001));
  jam::LammpsImport r = from_time(none);
  r.rate = 1e-3;  // stated on the command line, not by the log
  refused(r, {none.path.string() + ": no fix deform line", "--column volume=Volume"});
  const Log late = write_log("late_deform", kHead + run_block(0, 200, 0.001) + kDeform);
  refused(from_time(late), {late.path.string() + ":13: fix compress deform comes after"});
}

BOOST_AUTO_TEST_CASE(the_bundled_inputs_route_refuses_a_second_run) {
  const fs::path ref = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps" / "inertial-2d";
  const fs::path d = scratch("bundled");
  // The stored log, then a second run of the same thermo (a relaxation after it).
  std::string text = jam::test::slurp(ref / "lammps.log");
  text +=
      "run 100\nStep Time c_virial PotEng v_Z\n400 4 0.001 1e-6 3\n500 5 0.001 1e-6 3\n"
      "Loop time of 0.1 on 1 procs for 100 steps with 256 atoms\n";
  std::ofstream(d / "lammps.log") << text;
  jam::LammpsImport r;
  r.log = (d / "lammps.log").string();
  r.data = (ref / "start.data").string();
  r.out = (d / "run.h5").string();
  try {
    jam::import_lammps_run(r);
    BOOST_FAIL("a log of two runs was imported");
  } catch (const std::runtime_error& e) {
    BOOST_TEST(std::string(e.what()).find("a second run") != std::string::npos, e.what());
  }
  BOOST_TEST(!fs::exists(r.out));
  // The stored log alone imports.
  r.log = (ref / "lammps.log").string();
  jam::import_lammps_run(r);
  BOOST_TEST(fs::exists(r.out));
}
