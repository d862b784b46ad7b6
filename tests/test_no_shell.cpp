// No shell ever sees a path or a value: child processes start from an argument vector
// (sim/io/process.hpp), so names holding `;`, `$( )`, quotes or blanks are only names. The
// LAMMPS check runs in a campaign directory with such a name, and a campaign directory that
// does not exist is a tool error (exit 2), not created.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "process.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-no-shell-" + std::to_string(::getpid()));

// Names a shell would act on: command separators, substitutions, quotes, globs and blanks.
const std::vector<std::string> kHostileNames = {"b;touch pwned;x",
                                                "$(touch pwned)",
                                                "`touch pwned`",
                                                "it's",
                                                "say \"x\"",
                                                "two words",
                                                "a&&touch pwned",
                                                "*",
                                                "-n",
                                                "x>pwned"};

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

/// Nothing named "pwned" anywhere under dir or in the working directory.
bool nothing_injected(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename() == "pwned") return false;
  }
  return !fs::exists("pwned");
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(no_shell, Fixture)

// Each argument arrives as one argument, byte for byte, and a working directory with any of
// these names is entered, not interpreted.
BOOST_AUTO_TEST_CASE(arguments_and_directories_pass_verbatim) {
  for (const auto& name : kHostileNames) {
    BOOST_TEST_CONTEXT("name " << name) {
      const fs::path dir = kDir / name;
      fs::create_directories(dir);
      jam::ProcessOptions o;
      o.working_directory = dir;
      o.stdout_file = (kDir / "out.txt").string();
      BOOST_TEST(jam::run_program({"printf", "%s|", name, "pwd", name}, o) == 0);
      BOOST_TEST(slurp(kDir / "out.txt") == name + "|pwd|" + name + "|");
      BOOST_TEST(jam::run_program({"pwd"}, o) == 0);
      BOOST_TEST(slurp(kDir / "out.txt") == fs::canonical(dir).string() + "\n");
    }
  }
  BOOST_TEST(nothing_injected(kDir));
}

BOOST_AUTO_TEST_CASE(exit_status_and_missing_program) {
  BOOST_TEST(jam::run_program({"false"}) == 1);
  BOOST_TEST(jam::run_program({"true"}) == 0);
  BOOST_CHECK_THROW(jam::run_program({"no-such-program-jam"}), std::runtime_error);
  BOOST_TEST(jam::find_program("no-such-program-jam").empty());
  BOOST_TEST(!jam::find_program("true").empty());
}

// An Open MPI program gets a session directory of its own (OMPI_MCA_orte_tmpdir_base): new and
// empty when it starts, a different one for each, gone when it has ended; other programs get
// none, and a base the caller's environment names is the caller's and is passed on as it is.
BOOST_AUTO_TEST_CASE(an_mpi_program_gets_a_session_directory_of_its_own) {
  const char* kBase = "OMPI_MCA_orte_tmpdir_base";
  const char* before = std::getenv(kBase);
  const std::string saved = before ? before : "";
  ::unsetenv(kBase);
  const fs::path out = kDir / "session.txt";
  auto session = [&](bool mpi) {
    jam::ProcessOptions o;
    o.stdout_file = out.string();
    o.mpi_program = mpi;
    const std::string probe =
        "import os; b = os.environ.get('OMPI_MCA_orte_tmpdir_base', ''); "
        "print(b + ('|empty' if b and os.path.isdir(b) and not os.listdir(b) else '|none'))";
    BOOST_TEST(jam::run_program({"/usr/bin/python3", "-c", probe}, o) == 0);
    std::string line = slurp(out);
    return line.substr(0, line.find('\n'));
  };
  const std::string first = session(true), second = session(true);
  const fs::path temp = (fs::temp_directory_path() / "x").parent_path();  // without a final '/'
  for (const std::string& s : {first, second}) {
    const fs::path dir = s.substr(0, s.find('|'));
    BOOST_TEST(dir.parent_path() == temp, s);
    BOOST_TEST(dir.filename().string().rfind("jam-mpi-", 0) == 0, s);
    BOOST_TEST(s.substr(s.find('|')) == "|empty", s);
    BOOST_TEST(!fs::exists(dir), s);
  }
  BOOST_TEST(first != second);
  BOOST_TEST(session(false) == "|none");
  ::setenv(kBase, kDir.c_str(), 1);
  BOOST_TEST(session(true) == kDir.string() + "|none");  // kDir holds session.txt: not empty
  if (before) {
    ::setenv(kBase, saved.c_str(), 1);
  } else {
    ::unsetenv(kBase);
  }
}

// The LAMMPS check starts lmp in DIR/lammps-check/...: with DIR named to break a shell command
// line it still runs (or, without lmp, reads the stored result) and nothing is injected.
BOOST_AUTO_TEST_CASE(lammps_check_in_a_hostile_directory) {
  const fs::path dir = kDir / "b;touch pwned;x $(touch pwned) 'q\"";
  fs::create_directories(dir);
  const auto o = jam::test::run_logged(
      kDir / "log.txt", {JAM_EXECUTABLE, "check", "lammps", dir.string(), "--reference-dir",
                         (fs::path(JAM_SOURCE_DIR) / "reference").string()});
  BOOST_TEST((o.status == 0 || o.status == 1), o.output);  // verdicts, not a tool error
  BOOST_TEST(fs::exists(dir / "checks-lammps.json"), o.output);
  BOOST_TEST(nothing_injected(kDir));
}

BOOST_AUTO_TEST_CASE(check_on_a_missing_directory_is_a_tool_error) {
  for (const char* check : {"lammps", "all", "finite_size"}) {
    const fs::path missing = kDir / "no-such-campaign";
    const auto o =
        jam::test::run_logged(kDir / "log.txt", {JAM_EXECUTABLE, "check", check, missing.string()});
    BOOST_TEST(o.status == 2, check << ": " << o.output);
    BOOST_TEST(o.output.find("no such campaign directory") != std::string::npos, o.output);
    BOOST_TEST(!fs::exists(missing));
  }
}

BOOST_AUTO_TEST_SUITE_END()
