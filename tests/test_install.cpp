// The installed tree works without the source tree: `cmake --install` into a temporary prefix,
// then the installed jam runs a small campaign, its statistics, every check (the LAMMPS check
// from the installed stored results) and the report (installed report scripts and jamio) with
// the source tree hidden: a private mount namespace with an empty tmpfs over it (root only;
// skipped with a message otherwise).
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "process.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-install-" + std::to_string(::getpid()));

/// Runs argv with the source tree hidden; 125 when the namespace could not be made.
int run_hidden(const std::vector<std::string>& argv, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(out, 2);
    if (::unshare(CLONE_NEWNS) != 0 ||
        ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        ::mount("tmpfs", JAM_SOURCE_DIR, "tmpfs", 0, "size=1m") != 0) {
      ::_exit(125);
    }
    std::vector<char*> args;
    std::vector<std::string> copy = argv;
    for (auto& a : copy) args.push_back(a.data());
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace

BOOST_AUTO_TEST_CASE(installed_jam_runs_without_the_source_tree) {
  fs::create_directories(kDir);
  const fs::path prefix = kDir / "prefix";
  BOOST_TEST_REQUIRE(
      jam::test::run_logged(kDir / "install.txt",
                            {"cmake", "--install", JAM_BUILD_DIR, "--prefix", prefix.string()})
              .status == 0,
      slurp(kDir / "install.txt"));
  const std::string jam = (prefix / "bin" / "jam").string();
  BOOST_TEST_REQUIRE(fs::exists(prefix / "share/jam/reference/lammps/compress_inertial.in"));
  BOOST_TEST_REQUIRE(fs::exists(prefix / "share/jam/reports/jam_report.py"));

  const fs::path log = kDir / "log.txt";
  const int probe = run_hidden({"/bin/true"}, log);
  if (probe == 125) {
    BOOST_TEST_MESSAGE("skipped: hiding the source tree needs root (mount namespaces)");
    fs::remove_all(kDir);
    return;
  }
  BOOST_TEST_REQUIRE(probe == 0);
  // Hidden indeed: the source tree is empty inside.
  BOOST_TEST(run_hidden({"/usr/bin/test", "-e", std::string(JAM_SOURCE_DIR) + "/CMakeLists.txt"},
                        log) == 1);

  const fs::path campaign = kDir / "c.toml";
  std::ofstream(campaign) << "name = \"inst\"\ndim = 2\nsizes = [64, 128]\nphi_init = [0.7]\n"
                             "log10_rates = [-2.5, -3.0]\nsamples = 3\nphi_stop = 0.8\n"
                             "phi_step = 0.005\nseed = 4\noutput = \""
                          << (kDir / "runs").string() << "\"\n";
  const std::string dir = (kDir / "runs").string();
  BOOST_TEST(run_hidden({jam, "campaign", "run", "--quiet", campaign.string()}, log) == 0,
             slurp(log));
  BOOST_TEST(run_hidden({jam, "stats", dir}, log) == 0, slurp(log));
  // --with-lammps: the self-checks read the installed reference data, which is what is tested.
  const int check = run_hidden({jam, "check", "all", dir, "--no-lmp", "--with-lammps"}, log);
  BOOST_TEST((check == 0 || check == 1 || check == 3), slurp(log));  // verdicts, not an error
  BOOST_TEST(slurp(kDir / "runs" / "checks.json").find("stored LAMMPS result") !=
             std::string::npos);  // read from the installed reference data
  BOOST_TEST(
      run_hidden({jam, "report", dir, "--out", (kDir / "report").string(), "--quiet"}, log) == 0,
      slurp(log));
  BOOST_TEST(fs::exists(kDir / "report" / "index.html"));
  fs::remove_all(kDir);
}
