// Every bad input of `jam sim` is rejected with a one-line error naming the option and the
// value, a non-zero exit status, and no output file.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/run/sim_config.hpp"

namespace fs = std::filesystem;

namespace {

struct Outcome {
  int status;
  std::string stderr_text;
};

const fs::path kDir = fs::temp_directory_path() / ("jam-bad-input-" + std::to_string(::getpid()));

Outcome run_jam(const std::string& args) {
  fs::create_directories(kDir);
  const auto o = jam::test::run_jam_stderr(kDir / "stderr.txt", "sim " + args);
  return {o.status, o.output};
}

void expect_rejected(const std::string& args, const std::string& must_mention) {
  const std::string out = (kDir / "out.h5").string();
  fs::remove(out);
  const Outcome o = run_jam(args + " --quiet --out " + out);
  BOOST_TEST_CONTEXT("jam sim " << args) {
    BOOST_TEST(o.status != 0);
    BOOST_TEST(o.stderr_text.find(must_mention) != std::string::npos, o.stderr_text);
    BOOST_TEST(std::count(o.stderr_text.begin(), o.stderr_text.end(), '\n') == 1);
    BOOST_TEST(!fs::exists(out));
    for (const auto& e : fs::directory_iterator(kDir)) {
      BOOST_TEST(e.path().string().find(".partial") == std::string::npos, e.path());
    }
  }
}

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Whether `jam --version` prints `text` (how this jam was built).
bool jam_says(const std::string& text) {
  fs::create_directories(kDir);
  const auto version = jam::test::run_logged(kDir / "version.txt", {JAM_EXECUTABLE, "--version"});
  BOOST_REQUIRE(version.status == 0);
  return version.output.find(text) != std::string::npos;
}

std::string replace_first(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  BOOST_TEST_REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

BOOST_AUTO_TEST_CASE(bad_numbers) {
  expect_rejected("--n 1023", "--n 1023");
  expect_rejected("--n 0", "--n 0");
  expect_rejected("--n 1", "--n 1");
  expect_rejected("--phi-init 0.9 --phi-stop 0.86", "--phi-init 0.9");
  expect_rejected("--phi-init 0.86 --phi-stop 0.86", "--phi-init 0.86");
  expect_rejected("--rate 0", "--rate 0");
  expect_rejected("--rate -1e-4", "--rate -0.0001");
  expect_rejected("--dt 0", "--dt 0");
  expect_rejected("--dt -0.01", "--dt -0.01");
  expect_rejected("--dim 4", "--dim 4");
  expect_rejected("--n abc", "abc");
  expect_rejected("--rate nan", "--rate nan");
  expect_rejected("--dynamics inertial --q 0.03 --dt 0.01", "--dt 0.01");
  expect_rejected("--integrator rk4", "--integrator rk4");
  expect_rejected("--relax-energy -1", "--relax-energy -1");
  expect_rejected("--skin 0", "--skin 0");
  expect_rejected("--threads 0", "--threads 0");
  expect_rejected("--threads 100000", "--threads 100000");
}

BOOST_AUTO_TEST_CASE(grossly_unstable_time_step) {
  // Far beyond the stability bound of either integrator: an error naming --dt and the safe
  // bound within a bounded number of steps (here at the start), not a quietly wrong run file.
  // The bound itself is tested in test_stability.
  // (--phi-step 0.01: a step of dt 5 compresses by 0.0086, within one output interval.)
  expect_rejected(
      "--n 256 --phi-init 0.8 --phi-stop 0.86 --rate 1e-3 --integrator heun --dt 5 --phi-step 0.01",
      "--dt 5: unstable for heun");
  expect_rejected(
      "--n 256 --phi-init 0.8 --phi-stop 0.86 --rate 1e-3 --dt 5 --phi-step 0.01 "
      "--integrator euler",
      "--dt 5: unstable for euler");
}

BOOST_AUTO_TEST_CASE(box_too_small) {
  expect_rejected("--n 4 --phi-init 0.5", "--n 4");
  expect_rejected("--n 8 --dim 3 --phi-init 0.3 --phi-stop 0.6", "--n 8");
}

BOOST_AUTO_TEST_CASE(unknown_option) {
  expect_rejected("--bogus 3", "--bogus");
}

BOOST_AUTO_TEST_CASE(unwritable_output) {
  const Outcome o = run_jam("--n 64 --quiet --out /nonexistent-dir/run.h5");
  BOOST_TEST(o.status != 0);
  BOOST_TEST(o.stderr_text.find("--out /nonexistent-dir/run.h5") != std::string::npos,
             o.stderr_text);
}

// The number forms LAMMPS and other writers use (a sign, an exponent in either case, tabs,
// CRLF line ends, comments) read as the same bits as the plain form; what is not one number
// is refused with its line and field.
BOOST_AUTO_TEST_CASE(data_files_read_every_number_form_the_same) {
  const auto read = [](const std::string& text) {
    std::istringstream in(text);
    return jam::read_lammps_data<2>(in, "forms.data");
  };
  const std::string plain =
      "t\n\n2 atoms\n2 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n-0.5 0.5 zlo zhi\n\n"
      "Atoms # atomic\n\n1 1 1.5 2.25 0\n2 2 7.125 0.001 0\n";
  const std::string forms =
      "t\r\n\r\n 2\tatoms\r\n2 atom types # two\r\n\r\n+0 1E1 xlo xhi\r\n0.0 10.000 ylo "
      "yhi\r\n-5e-1 +0.5e+0 zlo zhi\r\n\r\nAtoms\r\n\r\n\t1 1 +1.5 225e-2 -0 0 0 0\r\n"
      "2 2.0 7.125E0 1e-3 0.0 # last\r\n";
  const auto a = read(plain), b = read(forms);
  BOOST_TEST(a.box_length == 10.0);
  BOOST_TEST(b.box_length == a.box_length);
  BOOST_TEST_REQUIRE(b.particles.size() == 2u);
  for (int d = 0; d < 2; ++d)
    for (std::size_t i = 0; i < 2; ++i) {
      BOOST_TEST(b.particles.s[d][i] == a.particles.s[d][i]);
      BOOST_TEST(b.particles.type[i] == a.particles.type[i]);
    }
  BOOST_TEST(a.particles.s[0][0] == 1.5 / 10.0);
  BOOST_TEST(a.particles.s[1][1] == 0.001 / 10.0);
  for (const char* bad : {"0x1p0", "1.5.2", "+-1", "++1", "1,5", "1e", "--1"}) {
    std::string text = plain;
    text.replace(text.find("7.125"), 5, bad);
    try {
      read(text);
      BOOST_ERROR("accepted x = " << bad);
    } catch (const std::runtime_error& e) {
      BOOST_TEST(std::string(e.what()).find("forms.data:13: x: '" + std::string(bad) + "'") == 0u,
                 e.what());
    }
  }
}

BOOST_AUTO_TEST_CASE(unreadable_or_bad_data_files) {
  expect_rejected("--read-lammps-data /nonexistent.data", "--read-lammps-data /nonexistent.data");
  const fs::path bad = kDir / "bad.data";
  fs::create_directories(kDir);
  const std::string header =
      "title\n\n4 atoms\n2 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n-0.5 0.5 zlo zhi\n\n";
  write_file(bad, header + "Atoms # atomic\n\n1 1 1 1 0\n2 1 2 2 0\n3 3 3 3 0\n4 2 4 4 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":14: atom type: 3");
  write_file(bad, header + "Atoms # atomic\n\n1 1 1 1 0\n2 1 2 x 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":13: y: 'x'");
  write_file(bad, header + "Atoms # atomic\n\n1 1 1 1 0\n2 1 2 2 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), "file ends after 2 of 4 atoms");
  write_file(bad, "title\n\n4 atoms\n0 10 xlo xhi\n0 12 ylo yhi\n\nAtoms\n\n");
  expect_rejected("--read-lammps-data " + bad.string(), "not square");
  write_file(bad, header + "Bonds\n\n");
  expect_rejected("--read-lammps-data " + bad.string(), "unsupported section 'Bonds'");
  // Non-finite and absurd numbers, negative or huge counts, garbage, truncation: each is named
  // with file, line and field.
  const std::string atoms = "Atoms # atomic\n\n1 1 1 1 0\n2 1 6 6 0\n3 2 1 6 0\n";
  write_file(bad, header + atoms + "4 2 nan 1 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: x: 'nan'");
  write_file(bad, header + atoms + "4 2 1 -inf 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: y: '-inf'");
  write_file(bad, header + atoms + "4 2 1e300 1 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: x: 1e300 is far");
  write_file(bad, header + atoms + "4 2 1 1 0.5\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: z: 0.5");
  write_file(bad, header + atoms + "4 2 1 1\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: atom line has 4");
  write_file(bad, header + atoms + "3 2 1 1 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: atom id: 3");
  write_file(bad, header + atoms + "4.5 2 1 1 0\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":15: atom id: '4.5'");
  write_file(bad, replace_first(header, "4 atoms", "-4 atoms") + atoms);
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":3: atoms: -4");
  write_file(bad, replace_first(header, "4 atoms", "99999999999 atoms") + atoms);
  expect_rejected("--read-lammps-data " + bad.string(), "atoms: 99999999999 (at most");
  write_file(bad, replace_first(header, "0 10 xlo", "10 0 xlo") + atoms);
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":6: xlo xhi: empty box");
  write_file(bad, replace_first(header, "0 10 xlo", "-1e308 1e308 xlo") + atoms);
  expect_rejected("--read-lammps-data " + bad.string(), "not finite");
  write_file(bad, header + atoms + "4 2 4 4 0\n\nAtoms\n\n");
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":17: a second Atoms");
  write_file(bad, header.substr(0, 30));  // truncated inside the header
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":");
  write_file(bad, std::string("\x7f"
                              "ELF\x02\x01\x01\0\0\0garbage\n\x01\x02 atoms\n",
                              27));
  expect_rejected("--read-lammps-data " + bad.string(), bad.string() + ":");
  write_file(bad, "");
  expect_rejected("--read-lammps-data " + bad.string(), "no Atoms section");
  // A file that is fine is accepted, but --n alongside it is a conflict.
  write_file(bad, header + "Atoms # atomic\n\n1 1 1 1 0\n2 1 6 6 0\n3 2 1 6 0\n4 2 6 1 0\n");
  expect_rejected("--n 4 --read-lammps-data " + bad.string(), "--n 4");
  fs::remove_all(kDir);
}

// Seeds lie in [0, 2^63 - 1]: anything else is refused naming the value, never wrapped (-1,
// 2^64 and 10^23 all used to store seed -1, so different seeds gave the same run).
BOOST_AUTO_TEST_CASE(seeds_out_of_range) {
  for (const char* seed : {"-1", "99999999999999999999999", "18446744073709551616",
                           "9223372036854775808", "1.5", "0x10", "+3"}) {
    expect_rejected(std::string("--n 64 --seed ") + seed, std::string("--seed: ") + seed);
  }
  BOOST_TEST(jam::parse_seed("seed", "9223372036854775807") == jam::kMaxSeed);
  BOOST_TEST(jam::parse_seed("seed", "0") == 0u);
  const std::string out = (kDir / "max-seed.h5").string();
  const Outcome o = run_jam(
      "--n 64 --phi-init 0.7 --phi-stop 0.72 --rate 1e-2 --phi-step 0.005 "
      "--seed 9223372036854775807 --quiet --out " +
      out);
  BOOST_TEST(o.status == 0, o.stderr_text);
  BOOST_TEST(jam::h5::File::open_read(out).read_attribute_int("seed") ==
             std::int64_t{9223372036854775807});
}

// Typos that would run for ever or exhaust memory are refused with the estimate, before any
// allocation; a step that jumps over output points is refused with the largest dt that does not.
BOOST_AUTO_TEST_CASE(absurd_costs) {
  expect_rejected("--phi-step 1e-12 --dt 1e-12 --rate 1e-4",
                  "--phi-step 1e-12: 2.6e+11 output points");
  // (Heun: its step is dt. The Chebyshev integrator lands on every output point.)
  expect_rejected("--integrator heun --rate 1", "--rate 1: one step of --dt 0.1 compresses by");
  expect_rejected("--integrator heun --dt 1e-300", "--dt 1e-300: 1.8e+303 compression steps");
  expect_rejected("--rate 1e-300", "--rate 1e-300, more than the limit 1e+10");
  // 1.25 x 296 B per particle (the Chebyshev integrator in 2D, integrator_list.hpp) x 2e9.
  expect_rejected("--n 2000000000", "--n 2000000000: an estimated 740 GB of memory");
  expect_rejected("--dynamics inertial --q 1e300 --dt 0.01", "--q 1e+300: must be in (0, 1]");
  // --force lifts the limits (not the jump, whose results would be wrong).
  jam::SimConfig c;
  c.integrator = "heun";
  c.phi_step = 1e-8;
  c.dt = 1e-6;
  c.compression_rate = 1e-3;
  BOOST_CHECK_THROW(jam::validate_cost(c, 1024, false), jam::ConfigError);
  BOOST_CHECK_NO_THROW(jam::validate_cost(c, 1024, true));
  c.compression_rate = 1.0;
  BOOST_CHECK_THROW(jam::validate_cost(c, 1024, true), jam::ConfigError);
}

// A jam built without MPI, started by mpirun or srun as one of several processes, would run
// the whole campaign in each of them. It refuses in one line instead. Only a build without MPI
// can show this (the sanitizer build, scripts/sanitize.sh); a build with MPI skips it.
BOOST_AUTO_TEST_CASE(jam_without_mpi_refuses_to_run_as_one_of_several_processes) {
  if (!jam_says("MPI: no")) {
    BOOST_TEST_MESSAGE("this jam is built with MPI: skipped");
    return;
  }
  for (const char* launcher : {"OMPI_COMM_WORLD_SIZE=2", "PMI_SIZE=4", "PMIX_SIZE=2"}) {
    const auto o =
        jam::test::run_logged(kDir / "mpi.txt", {"env", launcher, JAM_EXECUTABLE, "sim", "--quiet",
                                                 "--n", "64", "--out", (kDir / "mpi.h5").string()});
    BOOST_TEST_CONTEXT(launcher) {
      BOOST_TEST(o.status == 2, o.output);
      BOOST_TEST(o.output.find("this jam was built without MPI") != std::string::npos, o.output);
      BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') == 1, o.output);
      BOOST_TEST(!fs::exists(kDir / "mpi.h5"));
    }
  }
}

// A jam built with MPI loads its MPI module (campaign/mpi_module.hpp) only under a launcher,
// from <prefix>/lib/jam/ when installed. A module there that is not jam's stops the process
// with one line naming the file, before anything is written; outside a launcher the module is
// never looked at.
BOOST_AUTO_TEST_CASE(an_unusable_mpi_module_is_refused_in_one_line) {
  if (!jam_says("MPI: yes")) {
    BOOST_TEST_MESSAGE("this jam is built without MPI: skipped");
    return;
  }
  const fs::path prefix = kDir / "installed";
  fs::create_directories(prefix / "bin");
  fs::create_directories(prefix / "lib" / "jam");
  const fs::path jam = prefix / "bin" / "jam";
  fs::copy_file(JAM_EXECUTABLE, jam, fs::copy_options::overwrite_existing);
  const fs::path module = prefix / "lib" / "jam" / "jam-mpi.so";
  std::ofstream(module) << "not a shared library\n";
  const fs::path out = kDir / "module.h5";
  const std::vector<std::string> sim = {jam.string(), "sim",  "--quiet", "--n",       "64",
                                        "--phi-stop", "0.61", "--out",   out.string()};
  std::vector<std::string> launched = {"env", "OMPI_COMM_WORLD_SIZE=2"};
  launched.insert(launched.end(), sim.begin(), sim.end());
  const auto o = jam::test::run_logged(kDir / "module.txt", launched);
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(o.output.find("MPI module " + module.string()) != std::string::npos, o.output);
  BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') == 1, o.output);
  BOOST_TEST(!fs::exists(out));
  // Without a launcher the same jam runs.
  const auto plain = jam::test::run_logged(kDir / "plain.txt", sim);
  BOOST_TEST(plain.status == 0, plain.output);
  BOOST_TEST(fs::exists(out));
}
