// The open run format (docs/cross-simulator.md) and its importers: a run written and read back
// is what was written; every rule of the spec refuses a file that breaks it, naming the field,
// and leaves nothing behind; a LAMMPS run of any input made by the test imports with its
// columns named (and is refused when its box does not shrink at the stated rate); configuration
// frames are measured by jam to the analytic pressure, Z and energy of an overlapping pair.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "process.hpp"
#include "sim/io/frames_import.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_import.hpp"
#include "sim/io/open_run.hpp"
#include "sim/run/sim_config.hpp"

namespace fs = std::filesystem;
using jam::OpenRun;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("jam_test_open_runs_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A valid run: 2D, N 64, rate 1e-3, phi from the time.
OpenRun sound_run() {
  OpenRun r;
  r.dim = 2;
  r.n = 64;
  r.compression_rate = 1e-3;
  r.phi_init = 0.8;
  r.simulator = "test-code";
  r.simulator_version = "0.1";
  r.sample = 3;
  for (int k = 0; k < 5; ++k) {
    const double t = 2.0 * k;
    r.time.push_back(t);
    r.packing_fraction.push_back(0.8 * std::exp(2 * 1e-3 * t));
    r.pressure.push_back(1e-3 * k);
    r.contacts_per_particle.push_back(0.5 * k);
  }
  return r;
}

/// Writing `r` fails with a message naming `field`, and leaves the directory empty.
void refused(const OpenRun& r, const std::string& field) {
  const fs::path d = scratch("refused");
  BOOST_TEST_CONTEXT("field " << field) {
    try {
      jam::write_open_run((d / "run.h5").string(), r);
      BOOST_FAIL("a run with a bad " + field + " was written");
    } catch (const std::runtime_error& e) {
      BOOST_TEST(std::string(e.what()).find(field) != std::string::npos, e.what());
    }
    BOOST_TEST(fs::is_empty(d));
  }
}

/// The open run's attributes of a frames file of one small and one big particle in 2D.
void frames_attributes(jam::h5::File& f, double phi_init) {
  f.write_attribute("dim", std::int64_t{2});
  f.write_attribute("n", std::int64_t{2});
  f.write_attribute("diameter_ratio", 1.4);
  f.write_attribute("contact", std::string("harmonic"));
  f.write_attribute("compression_rate", 1e-3);
  f.write_attribute("phi_init", phi_init);
  f.write_attribute("simulator", std::string("hoomd-blue"));
  f.write_attribute("simulator_version", std::string("4"));
  f.write_attribute("sample", std::int64_t{0});
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_run_reads_back_as_written) {
  const fs::path d = scratch("round_trip");
  const OpenRun r = sound_run();
  jam::write_open_run((d / "run.h5").string(), r);
  const OpenRun back = jam::read_open_run((d / "run.h5").string());
  BOOST_TEST(!back.jam_native);
  BOOST_TEST(back.dim == 2);
  BOOST_TEST(back.n == 64);
  BOOST_TEST(back.sample == 3);
  BOOST_TEST(back.simulator == "test-code");
  BOOST_TEST(back.packing_fraction == r.packing_fraction, boost::test_tools::per_element());
  BOOST_TEST(back.pressure == r.pressure, boost::test_tools::per_element());
  BOOST_TEST(back.contacts_per_particle == r.contacts_per_particle,
             boost::test_tools::per_element());
  BOOST_TEST(back.energy_per_particle.empty());
}

BOOST_AUTO_TEST_CASE(every_rule_of_the_spec_refuses_naming_the_field) {
  auto with = [](auto change) {
    OpenRun r = sound_run();
    change(r);
    return r;
  };
  refused(with([](OpenRun& r) { r.dim = 4; }), "dim");
  refused(with([](OpenRun& r) { r.n = 63; }), "n 63");
  refused(with([](OpenRun& r) { r.diameter_ratio = 2.5; }), "diameter_ratio");
  refused(with([](OpenRun& r) { r.contact = "linear"; }), "contact");
  refused(with([](OpenRun& r) { r.dynamics = "inertial"; }), "q");
  refused(with([](OpenRun& r) { r.compression_rate = NAN; }), "compression_rate");
  refused(with([](OpenRun& r) { r.phi_init = 1.2; }), "phi_init");
  refused(with([](OpenRun& r) { r.simulator.clear(); }), "simulator");
  refused(with([](OpenRun& r) { r.sample = -1; }), "sample");
  refused(with([](OpenRun& r) { r.pressure[2] = -1; }), "pressure[2]");
  refused(with([](OpenRun& r) { r.pressure[1] = INFINITY; }), "pressure[1]");
  refused(with([](OpenRun& r) { r.pressure.pop_back(); }), "pressure has 4 points");
  refused(with([](OpenRun& r) { std::swap(r.packing_fraction[1], r.packing_fraction[2]); }),
          "packing_fraction[2]");
  refused(with([](OpenRun& r) { r.contacts_per_particle[0] = -0.5; }), "contacts_per_particle[0]");
  // The box must shrink at the stated rate: phi(t) = phi_init exp(D rate t).
  refused(with([](OpenRun& r) { r.compression_rate = 2e-3; }), "does not shrink at the stated rate");
}

BOOST_AUTO_TEST_CASE(a_reader_checks_shape_before_value) {
  const fs::path d = scratch("shapes");
  jam::write_open_run((d / "run.h5").string(), sound_run());
  // A table where a list belongs: same values, rank 2.
  {
    jam::h5::File f = jam::h5::File::create((d / "table.h5").string());
    f.write_attribute("format", std::string(jam::kOpenRunFormat));
    f.write_attribute("format_version", std::int64_t{1});
    f.write_attribute("protocol", std::string(jam::kOpenRunProtocol));
    f.write_attribute("units", std::string("jam"));
    f.write_attribute("dim", std::int64_t{2});
    f.write_attribute("n", std::int64_t{64});
    f.write_attribute("diameter_ratio", 1.4);
    f.write_attribute("contact", std::string("harmonic"));
    f.write_attribute("dynamics", std::string("overdamped"));
    f.write_attribute("compression_rate", 1e-3);
    f.write_attribute("phi_init", 0.8);
    f.write_attribute("simulator", std::string("x"));
    f.write_attribute("simulator_version", std::string(""));
    f.write_attribute("sample", std::int64_t{0});
    std::vector<double> phi = {0.80, 0.81, 0.82, 0.83};
    f.write_dataset("packing_fraction", phi, {2, 2});
    f.write_dataset("pressure", std::vector<double>{0, 0, 0, 0});
    f.close();
  }
  try {
    jam::read_open_run((d / "table.h5").string());
    BOOST_FAIL("a rank-2 packing_fraction was read");
  } catch (const std::runtime_error& e) {
    BOOST_TEST(std::string(e.what()).find("rank 2") != std::string::npos, e.what());
  }
}

BOOST_AUTO_TEST_CASE(frames_are_measured_to_the_analytic_pair) {
  // One small and one big particle, 2D, at distance r = 1.1 < d_ij = 1.2 in a box of 10:
  // delta = 1 - r/d_ij, U = delta^2 / 2, |f| = delta / d_ij, p = |f| r / (D V), Z = 2/2.
  const fs::path d = scratch("frames");
  const double length = 10.0, r = 1.1, dij = 1.2, delta = 1 - r / dij;
  {
    jam::h5::File f = jam::h5::File::create((d / "frames.h5").string());
    frames_attributes(f, jam::packing_fraction_of(2, 2, 1.4, length));
    // Frame 2: the same pair seen across the periodic boundary, in a box shrunk at the rate.
    const double later = length * std::exp(-1e-3 * 5.0);
    f.write_dataset("box_length", std::vector<double>{length, later});
    f.write_dataset("time", std::vector<double>{0.0, 5.0});
    f.write_dataset("diameters", std::vector<double>{1.0, 1.4});
    f.write_dataset("positions",
                    std::vector<double>{0.0, 0.0, r, 0.0, -later / 2 + 0.05, 0.0, later / 2 - 1.05, 0.0},
                    {2, 2, 2});
    f.close();
  }
  jam::import_frames((d / "frames.h5").string(), (d / "run.h5").string());
  const OpenRun run = jam::read_open_run((d / "run.h5").string());
  // Round-off of a few operations on numbers of order 1: 1e-12 relative.
  const double p0 = (delta / dij) * r / (2 * length * length);
  BOOST_TEST(run.pressure[0] == p0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(run.energy_per_particle[0] == 0.5 * delta * delta / 2,
             boost::test_tools::tolerance(1e-12));
  BOOST_TEST(run.contacts_per_particle[0] == 1.0);
  const double later = length * std::exp(-1e-3 * 5.0);
  BOOST_TEST(run.pressure[1] == (delta / dij) * r / (2 * later * later),
             boost::test_tools::tolerance(1e-12));
  BOOST_TEST(run.interpolation.find("measured by jam") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(frames_in_a_box_jam_sim_refuses_are_refused) {
  // One small and one big particle 1.1 apart in a box of 2.2: the pair touches two images of
  // each other (p and Z twice one image's), which the minimum image counts once. jam sim
  // refuses such a box: 2.2 is not above 2 x (1.4 + skin 0.3) = 3.4; frames import does too.
  const fs::path d = scratch("frames_small_box");
  {
    jam::h5::File f = jam::h5::File::create((d / "frames.h5").string());
    frames_attributes(f, jam::packing_fraction_of(2, 2, 1.4, 10.0));
    f.write_dataset("box_length", std::vector<double>{10.0, 2.2});
    f.write_dataset("diameters", std::vector<double>{1.0, 1.4});
    f.write_dataset("positions", std::vector<double>{0, 0, 1.1, 0, 0, 0, 1.1, 0}, {2, 2, 2});
    f.close();
  }
  try {
    jam::import_frames((d / "frames.h5").string(), (d / "run.h5").string());
    BOOST_FAIL("frames in a box of 2.2 were imported");
  } catch (const std::runtime_error& e) {
    BOOST_TEST(std::string(e.what()).find("frame 1: box length 2.2 is not larger than twice the "
                                          "interaction range 2 x (1.4 + skin 0.3) = 3.4") !=
                   std::string::npos,
               e.what());
  }
  BOOST_TEST(!fs::exists(d / "run.h5"));
  // The same rule as jam sim's, at the same bound.
  jam::SimConfig c;
  c.n = 2;
  BOOST_CHECK_THROW(jam::validate_box(c, 2.2, 1.4), jam::ConfigError);
  BOOST_CHECK_NO_THROW(jam::validate_box(c, 3.41, 1.4));
  BOOST_TEST(jam::minimum_image_box_length(1.4, c.skin) == 3.4,
             boost::test_tools::tolerance(1e-15));
}

BOOST_AUTO_TEST_CASE(frames_of_another_model_are_refused) {
  const fs::path d = scratch("frames_bad");
  {
    jam::h5::File f = jam::h5::File::create((d / "frames.h5").string());
    frames_attributes(f, 0.1);
    f.write_dataset("box_length", std::vector<double>{10.0});
    f.write_dataset("diameters", std::vector<double>{1.0, 1.35});  // not the stated ratio
    f.write_dataset("positions", std::vector<double>{0, 0, 1, 0}, {1, 2, 2});
    f.close();
  }
  try {
    jam::import_frames((d / "frames.h5").string(), (d / "run.h5").string());
    BOOST_FAIL("frames with diameter 1.35 were imported as 1.4");
  } catch (const std::runtime_error& e) {
    BOOST_TEST(std::string(e.what()).find("diameters[1] = 1.35") != std::string::npos, e.what());
  }
  BOOST_TEST(!fs::exists(d / "run.h5"));
}

namespace {

/// A LAMMPS input of the test's own: 32 small and 32 big atoms at random at phi 0.8 (the box
/// from the model's diameters), the harmonic contact by table, overdamped-like drag, compressed
/// at 1e-3 for 200 steps; thermo Step Time c_virial PotEng v_Z Volume every 20 steps. The
/// rate is given through a variable, so the log does not state it literally.
void write_lammps_input(const fs::path& in, double length) {
  std::ofstream f(in);
  f.precision(17);
  f << "units lj\ndimension 2\nboundary p p p\natom_style atomic\n"
    << "region box block " << -length / 2 << " " << length / 2 << " " << -length / 2 << " "
    << length / 2 << " -0.5 0.5\n"
    << "create_box 2 box\n";
  // An 8 x 8 lattice, the types alternating, each site moved by up to 0.1 (a fixed pattern):
  // overlapping big pairs, no pair closer than the table's inner cutoff.
  for (int k = 0; k < 64; ++k) {
    const double a = length / 8, x = -length / 2 + a * (k % 8 + 0.5) + 0.1 * std::sin(k),
                 y = -length / 2 + a * (k / 8 + 0.5) + 0.1 * std::cos(3 * k);
    f << "create_atoms " << 1 + (k + k / 8) % 2 << " single " << x << " " << y << " 0\n";
  }
  f    << "mass 1 0.01\nmass 2 0.0196\n"
    << "pair_style table linear 1000\n"
    << "pair_coeff 1 1 ${table} SS 1.0\npair_coeff 1 2 ${table} SB 1.2\n"
    << "pair_coeff 2 2 ${table} BB 1.4\n"
    << "fix nve all nve\nfix drag all viscous 1.0\n"
    << "variable minus_rate equal -${rate}\n"
    << "fix compress all deform 1 x trate ${minus_rate} y trate ${minus_rate} remap x\n"
    << "fix flat all enforce2d\n"
    << "compute virial all pressure NULL virial\n"
    << "variable Z equal 0\n"
    << "thermo_style custom step time c_virial pe v_Z vol\n"
    << "thermo_modify format float %.17g\nthermo 20\ntimestep 0.01\nrun 200\n";
}

struct LammpsRun {
  fs::path dir, log;
  double length = 0;
};

/// Runs the input with LAMMPS (lmp on PATH; the test suite's set-up installs it).
LammpsRun lammps_run(const std::string& name) {
  LammpsRun r;
  r.dir = scratch(name);
  r.length = std::sqrt(32 * (M_PI / 4) * (1 + 1.4 * 1.4) / 0.8);
  write_lammps_input(r.dir / "in.compress", r.length);
  r.log = r.dir / "log.lammps";
  jam::ProcessOptions o;
  o.working_directory = r.dir;
  o.stdout_file = (r.dir / "screen").string();
  o.stderr_file = o.stdout_file;
  const std::string table = std::string(JAM_SOURCE_DIR) + "/reference/lammps/harmonic_contact.table";
  const int status = jam::run_program({"lmp", "-in", "in.compress", "-log", r.log.string(), "-var",
                                       "table", table, "-var", "rate", "1e-3"},
                                      o);
  BOOST_REQUIRE_MESSAGE(status == 0, "lmp failed: " + jam::test::slurp(r.dir / "screen"));
  return r;
}

jam::LammpsImport generic(const LammpsRun& run) {
  jam::LammpsImport l;
  l.log = run.log.string();
  l.out = (run.dir / "run.h5").string();
  l.columns = {{"pressure", "c_virial"}, {"volume", "Volume"}, {"time", "Time"},
               {"energy_per_particle", "PotEng"}};
  l.rate = 1e-3;
  l.diameter_ratio = 1.4;
  l.sample = 7;
  return l;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_lammps_log_of_any_input_imports_with_its_columns_named) {
  const LammpsRun run = lammps_run("lammps");
  jam::import_lammps_log(generic(run));
  const OpenRun r = jam::read_open_run((run.dir / "run.h5").string());
  BOOST_TEST(r.simulator == "lammps");
  BOOST_TEST(r.simulator_version.find("2021") != std::string::npos, r.simulator_version);
  BOOST_TEST(r.n == 64);  // from the 64 lines "Created 1 atoms"
  BOOST_TEST(r.dim == 2);  // from the log's dimension line
  BOOST_TEST(r.sample == 7);
  BOOST_TEST(r.packing_fraction.size() == 11u);  // steps 0, 20, ..., 200
  // The packing from the volume: the box side the test chose gives 0.8 at t = 0 (LAMMPS prints
  // 17 digits), and the rate's exp(D rate t) later; the reader checked the second to 1e-6.
  BOOST_TEST(r.phi_init == 0.8, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(r.packing_fraction.back() == 0.8 * std::exp(2 * 1e-3 * 2.0),
             boost::test_tools::tolerance(1e-9));
  BOOST_TEST(r.pressure[0] > 0);  // random overlaps
  BOOST_TEST(r.source_checksum.size() == 16u);
}

BOOST_AUTO_TEST_CASE(a_lammps_log_that_is_not_this_model_is_refused) {
  const LammpsRun run = lammps_run("lammps_bad");
  auto refused = [&](jam::LammpsImport l, const std::string& field) {
    BOOST_TEST_CONTEXT(field) {
      try {
        jam::import_lammps_log(l);
        BOOST_FAIL("imported");
      } catch (const std::runtime_error& e) {
        BOOST_TEST(std::string(e.what()).find(field) != std::string::npos, e.what());
      }
      BOOST_TEST(!fs::exists(run.dir / "run.h5"));
    }
  };
  jam::LammpsImport l = generic(run);
  l.rate = 2e-3;  // the log's fix deform says 1e-3
  refused(l, "--rate 0.002 but");
  // A log that does not state the rate (its fix deform line cut out): the box, measured by
  // the volume column, does not shrink at the rate the user states.
  {
    std::ifstream in(run.log);
    std::ofstream out(run.dir / "cut.log");
    for (std::string line; std::getline(in, line);)
      if (line.find("deform") == std::string::npos) out << line << "\n";
  }
  l.log = (run.dir / "cut.log").string();
  refused(l, "does not shrink at the stated rate");
  l = generic(run);
  l.diameter_ratio.reset();
  refused(l, "--diameter-ratio");
  l = generic(run);
  l.sample.reset();  // the run's identity within its ensemble: never guessed
  refused(l, "--sample: missing");
  l = generic(run);
  l.dim = 3;
  refused(l, "--dim 3");
  l = generic(run);
  l.n = 128;
  refused(l, "--n 128");
  l = generic(run);
  l.columns["pressure"] = "c_missing";
  refused(l, "c_missing");
  l = generic(run);
  l.phi_init = 0.75;
  refused(l, "--phi-init 0.75");
}
