// `jam check lammps`: passes against the stored LAMMPS result, fails when that result is
// perturbed (a particle moved by 1e-6, the pressure changed by 1e-3), and is inconclusive, never
// passed, when there is neither lmp nor a stored result.
#include <fmt/format.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "checks/lammps_check.hpp"
#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_import.hpp"
#include "sim/io/lammps_log.hpp"
#include "sim/io/process.hpp"
#include "sim/io/whole_number.hpp"

using namespace jam::checks;
namespace fs = std::filesystem;

namespace {

const fs::path kDir =
    fs::temp_directory_path() / ("jam-lammps-check-" + std::to_string(::getpid()));

LammpsCheckOptions stored_only(const fs::path& reference) {
  LammpsCheckOptions o;
  o.work_directory = (kDir / "work").string();
  o.reference_directory = reference.string();
  o.use_lmp = false;
  return o;
}

std::string status_of(const std::vector<Verdict>& v, const std::string& what) {
  for (const auto& x : v)
    if (x.case_name.rfind("2D", 0) == 0 && x.case_name.find(what) != std::string::npos)
      return x.status;
  return "missing";
}

void replace_in_file(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = jam::test::slurp(file);
  const auto at = text.find(from);
  BOOST_TEST_REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  std::ofstream(file) << text;
}

}  // namespace

BOOST_AUTO_TEST_CASE(stored_result_passes_and_perturbed_results_fail) {
  fs::create_directories(kDir);
  const fs::path original = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps";
  for (const auto& v : lammps_check(stored_only(original)))
    BOOST_TEST(v.status == "pass", v.case_name << ": " << v.reason);

  // A copy of the reference with one particle of the LAMMPS end state moved by 1e-6.
  const fs::path copy = kDir / "reference";
  fs::copy(original, copy, fs::copy_options::recursive);
  const fs::path end = copy / "inertial-2d" / "lammps_end.data";
  std::string text = jam::test::slurp(end);
  const auto atoms = text.find("Atoms");
  const auto line = text.find('\n', text.find('\n', atoms) + 1) + 1;  // first atom line
  std::istringstream in(text.substr(line, text.find('\n', line) - line));
  std::string id, type, x;
  in >> id >> type >> x;
  const double moved = std::stod(x) + 1e-6;
  replace_in_file(end, id + " " + type + " " + x,
                  id + " " + type + " " + fmt::format("{:.17g}", moved));
  BOOST_TEST(status_of(lammps_check(stored_only(copy)), "positions") == "fail");

  // The stored pressure changed by 1e-3 relative.
  fs::remove_all(copy);
  fs::copy(original, copy, fs::copy_options::recursive);
  const fs::path log = copy / "inertial-2d" / "lammps.log";
  std::string log_text = jam::test::slurp(log);
  const auto row = log_text.find("\n     400 ") + 1;
  std::istringstream r(log_text.substr(row, log_text.find('\n', row) - row));
  std::string step, time, p;
  r >> step >> time >> p;
  replace_in_file(log, p, fmt::format("{:.17g}", std::stod(p) * 1.001));
  BOOST_TEST(status_of(lammps_check(stored_only(copy)), "pressure") == "fail");

  // The overdamped comparison: LAMMPS pressures 3% higher in every stored log fail it.
  fs::remove_all(copy);
  fs::copy(original, copy, fs::copy_options::recursive);
  for (int k = 0; k < 4; ++k) {
    const fs::path f = copy / "overdamped-2d" / ("lammps_" + std::to_string(k) + ".log");
    std::istringstream in(jam::test::slurp(f));
    std::ostringstream out;
    bool thermo = false;
    for (std::string l; std::getline(in, l);) {
      if (l.rfind("Loop time", 0) == 0) thermo = false;
      if (thermo) {
        std::istringstream w(l);
        std::string step, time, pressure, rest;
        w >> step >> time >> pressure;
        std::getline(w, rest);
        l = step + " " + time + " " + fmt::format("{:.17g}", 1.03 * std::stod(pressure)) + rest;
      }
      if (l.rfind("Step Time c_virial", 0) == 0) thermo = true;  // header, not the comment
      out << l << "\n";
    }
    std::ofstream(f) << out.str();
  }
  BOOST_TEST(status_of(lammps_check(stored_only(copy)), "overdamped") == "fail");

  // Neither lmp (not used here) nor a stored result: inconclusive, never passed.
  fs::remove_all(copy / "inertial-2d");
  BOOST_TEST(status_of(lammps_check(stored_only(copy)), "") == "inconclusive");
  fs::remove_all(kDir);
}

BOOST_AUTO_TEST_CASE(import_turns_a_lammps_log_into_a_run_file) {
  fs::create_directories(kDir);
  const fs::path stored = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps" / "inertial-2d";
  const std::string out = (kDir / "imported.h5").string();
  jam::LammpsImport request;
  request.log = (stored / "lammps.log").string();
  request.data = (stored / "start.data").string();
  request.out = out;
  jam::import_lammps_run(request);
  const jam::h5::File f = jam::h5::File::open_read(out);
  BOOST_TEST(f.read_attribute_int("complete") == 1);
  BOOST_TEST(f.read_attribute_int("dim") == 2);
  BOOST_TEST(f.read_attribute_int("n") == 256);
  BOOST_TEST(f.read_attribute_double("q") == 0.1, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(f.read_attribute_double("compression_rate") == 1e-3);
  const auto phi = f.read_dataset("packing_fraction"), t = f.read_dataset("time"),
             p = f.read_dataset("pressure"), z = f.read_dataset("contacts_per_particle");
  BOOST_TEST_REQUIRE(phi.size() == 9u);  // thermo every 50 of 400 steps
  BOOST_TEST(f.read_dataset("energy_per_particle").size() == 9u);
  for (std::size_t k = 0; k < phi.size(); ++k) {
    BOOST_TEST(phi[k] == f.read_attribute_double("phi_init") * std::exp(2 * 1e-3 * t[k]),
               boost::test_tools::tolerance(1e-13));
    BOOST_TEST(std::abs(z[k] * 256 - std::round(z[k] * 256)) < 1e-9);  // whole contacts
  }
  BOOST_TEST(p.back() == 0.0015968148084278199, boost::test_tools::tolerance(1e-15));
  // A log without the thermo columns is refused, naming the file and line.
  std::ofstream(kDir / "bad.log")
      << "dimension 2\ntimestep 0.005\nfix c all deform 1 x trate -0.001\n"
      << "Step Time Temp\n0 0 1\n";
  request.log = (kDir / "bad.log").string();
  request.out = out + "2";
  BOOST_CHECK_EXCEPTION(jam::import_lammps_run(request), std::runtime_error,
                        [](const std::runtime_error& e) {
                          return std::string(e.what()).find(
                                     "bad.log: no thermo header with the columns Step Time "
                                     "c_virial PotEng v_Z") != std::string::npos;
                        });
  BOOST_TEST(!fs::exists(out + "2"));
  fs::remove_all(kDir);
}

// whole_number, under every count read as a double (log counts, TOML sizes and samples, sample
// ids, data-file integers): whole numbers in [lo, hi] pass with their bounds; fractions, NaN,
// infinities and whole numbers out of range do not.
BOOST_AUTO_TEST_CASE(whole_number_takes_whole_numbers_in_range_only) {
  using jam::kMaxExactWhole;
  using jam::whole_number;
  BOOST_TEST(whole_number(0.0, 0, 10).value_or(-1) == 0);
  BOOST_TEST(whole_number(-0.0, 0, 10).value_or(-1) == 0);
  BOOST_TEST(whole_number(10.0, 0, 10).value_or(-1) == 10);
  BOOST_TEST(whole_number(-7.0, -kMaxExactWhole, 0).value_or(0) == -7);
  BOOST_TEST(whole_number(0x1p53, 0, kMaxExactWhole).value_or(-1) == kMaxExactWhole);
  const double inf = std::numeric_limits<double>::infinity();
  for (const double v : {11.0, -1.0, 2.5, -0.5, 1e300, inf, -inf, std::nan("")}) {
    BOOST_TEST_CONTEXT(v) {
      BOOST_TEST(!whole_number(v, 0, 10));
    }
  }
  BOOST_TEST(!whole_number(0x1p53 + 2, 0, kMaxExactWhole));  // whole, one step past the bound
  BOOST_TEST(!whole_number(-0x1p53 - 2, -kMaxExactWhole, 0));
}

// Counts a log states (atoms, steps) are whole numbers a double holds exactly: 1e58 atoms, a
// fraction or a negative count is refused with the line and the value, never cast out of range
// (the fuzz target found "1111...1024 atoms", 59 digits). 2^53 itself is still a count.
BOOST_AUTO_TEST_CASE(counts_in_a_log_are_whole_numbers_in_range) {
  const std::vector<std::string> columns = {"Step", "Volume"};
  auto atoms = [&](const std::string& line) {
    std::istringstream in("dimension 2\n" + line + "\nStep Volume\n0 1\n10 0.9\nLoop\n");
    return jam::read_lammps_log(in, "t.log", columns).atoms;
  };
  BOOST_TEST(atoms("Created 1024 atoms").value_or(-1) == 1024);
  BOOST_TEST(atoms("  9007199254740992 atoms").value_or(-1) == 9007199254740992);
  for (const std::string line :
       {"  11111111111111111111111111111111111111111111111111111111024 atoms",
        "Created 2.5 atoms", "Created -3 atoms", "  9007199254740993.5 atoms"}) {
    BOOST_TEST_CONTEXT(line) {
      BOOST_CHECK_EXCEPTION(atoms(line), std::runtime_error, [](const std::runtime_error& e) {
        return std::string(e.what()).rfind("t.log:2: ", 0) == 0 &&
               std::string(e.what()).find("not a whole number in [0, 2^53]") != std::string::npos;
      });
    }
  }
  // Two lines of 2^53 atoms each: each a count, their sum not.
  BOOST_CHECK_THROW(atoms("Created 9007199254740992 atoms\nCreated 9007199254740992 atoms"),
                    std::runtime_error);

  // A thermo row whose Step is not whole is refused by the import, naming the row.
  fs::create_directories(kDir);
  const fs::path stored = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps" / "inertial-2d";
  fs::copy_file(stored / "lammps.log", kDir / "step.log", fs::copy_options::overwrite_existing);
  replace_in_file(kDir / "step.log", "      50 0.25 ", "      50.5 0.25 ");
  jam::LammpsImport request;
  request.log = (kDir / "step.log").string();
  request.data = (stored / "start.data").string();
  request.out = (kDir / "step.h5").string();
  BOOST_CHECK_EXCEPTION(jam::import_lammps_run(request), std::runtime_error,
                        [](const std::runtime_error& e) {
                          return std::string(e.what()).find(
                                     "thermo line 2: Step 50.5 is not a whole number") !=
                                 std::string::npos;
                        });
  BOOST_TEST(!fs::exists(kDir / "step.h5"));
  fs::remove_all(kDir);
}

// Why lmp failed, in the error jam raises: the log's first ERROR line, else the error output's
// (Open MPI's start-up failures), shown safely; a real lmp failure names LAMMPS's own error.
BOOST_AUTO_TEST_CASE(a_failed_lmp_is_named_by_its_first_error_line) {
  fs::create_directories(kDir);
  const std::string log = (kDir / "failed.log").string(), err = (kDir / "failed.err").string();
  std::ofstream(log) << "LAMMPS (7 Jan 2022)\nunits bogus\nERROR: Illegal units command "
                        "(src/update.cpp:410)\nLast command: units bogus\nERROR: a later one\n";
  std::ofstream(err) << "[vm:1] ORTE_ERROR_LOG: Error in file util/session_dir.c at line 107\n";
  BOOST_TEST(jam::lammps_failure_reason(log, err) ==
             "ERROR: Illegal units command (src/update.cpp:410)");
  std::ofstream(log) << "LAMMPS (7 Jan 2022)\n";  // no error in the log: the error output's
  BOOST_TEST(jam::lammps_failure_reason(log, err) ==
             "[vm:1] ORTE_ERROR_LOG: Error in file util/session_dir.c at line 107");
  const std::string missing = (kDir / "no-such.log").string();
  BOOST_TEST(jam::lammps_failure_reason(missing, missing) ==
             "neither its log nor its error output names an error");
  std::ofstream(err) << "ERROR: \x1b[31mred\x07 " << std::string(400, 'x') << "\n";
  const std::string shown = jam::lammps_failure_reason(log, err);
  BOOST_TEST(shown.rfind("ERROR: ?[31mred? xxx", 0) == 0, shown);
  BOOST_TEST(shown.size() == 243u, shown);  // 240 characters and "..."
  if (!jam::find_program("lmp").empty()) {
    std::ofstream(kDir / "bad.in") << "units bogus\n";
    jam::ProcessOptions o;
    o.working_directory = kDir;
    o.stdout_file = "/dev/null";
    o.stderr_file = err;
    o.mpi_program = true;
    BOOST_TEST(jam::run_program({"lmp", "-log", log, "-screen", "none", "-in", "bad.in"}, o) != 0);
    const std::string reason = jam::lammps_failure_reason(log, err);
    BOOST_TEST(reason.rfind("ERROR", 0) == 0, reason);
    BOOST_TEST(reason.find("units") != std::string::npos, reason);
  }
  fs::remove_all(kDir);
}
