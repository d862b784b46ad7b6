// What an output option may name (sim/io/output_path.hpp), checked before any work: a FIFO,
// a device node, a socket or a directory where a file belongs is refused in one line naming
// the option, and left as it was; a symbolic link is written through (its target replaced,
// the link kept); a link to nothing is refused; a campaign's output that is a file is refused.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/run/sim_config.hpp"

namespace fs = std::filesystem;
using jam::test::Outcome;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-outputs-" + std::to_string(::getpid()));

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

// A short run (N = 64, about 0.1 s).
Outcome sim_to(const fs::path& out) {
  return jam::test::run_jam_stderr(kDir / "err.txt",
                                   "sim --quiet --n 64 --phi-init 0.7 --phi-stop 0.72 --rate "
                                   "1e-2 --phi-step 0.005 --out " +
                                       out.string());
}

void expect_refused(const fs::path& out, const std::string& kind) {
  const auto before = fs::symlink_status(out).type();
  const Outcome o = sim_to(out);
  BOOST_TEST_CONTEXT(out) {
    BOOST_TEST(o.status == 2, o.output);
    BOOST_TEST(o.output.find("--out " + out.string() + ": is " + kind) != std::string::npos,
               o.output);
    BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') == 1, o.output);
    BOOST_TEST((fs::symlink_status(out).type() == before));  // left as it was
  }
  for (const auto& e : fs::directory_iterator(kDir)) {
    BOOST_TEST(e.path().string().find(".partial") == std::string::npos, e.path());
  }
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(output_paths, Fixture)

BOOST_AUTO_TEST_CASE(fifo_directory_and_socket_are_refused) {
  const fs::path fifo = kDir / "fifo";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  expect_refused(fifo, "a FIFO");
  fs::create_directories(kDir / "dir.h5");
  expect_refused(kDir / "dir.h5", "a directory");
  BOOST_TEST(sim_to(kDir / "dir.h5/").status == 2);

  const fs::path socket_path = kDir / "sock";
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
  BOOST_REQUIRE(::bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  expect_refused(socket_path, "a socket");
  ::close(s);
}

// A copy of /dev/full (as root; mknod needs privileges): never turned into a regular file.
BOOST_AUTO_TEST_CASE(device_node_is_refused) {
  const fs::path device = kDir / "full";
  if (::mknod(device.c_str(), S_IFCHR | 0666, ::makedev(1, 7)) != 0) {
    BOOST_TEST_MESSAGE("device_node_is_refused skipped: mknod needs root");
    return;
  }
  expect_refused(device, "a character device");
  BOOST_TEST(fs::is_character_file(device));
}

BOOST_AUTO_TEST_CASE(symbolic_links_are_written_through) {
  const fs::path target = kDir / "target.h5", link = kDir / "link.h5";
  std::ofstream(target) << "old";
  fs::create_symlink(target, link);
  const Outcome o = sim_to(link);
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(fs::is_symlink(link));
  BOOST_TEST(jam::run_file_problem(target.string()) == "");

  const fs::path dangling = kDir / "dangling.h5";
  fs::create_symlink(kDir / "nowhere.h5", dangling);
  expect_refused(dangling, "a symbolic link to a missing file");
  BOOST_TEST(!fs::exists(kDir / "nowhere.h5"));

  const fs::path to_fifo = kDir / "to-fifo";
  BOOST_REQUIRE(::mkfifo((kDir / "fifo2").c_str(), 0644) == 0);
  fs::create_symlink(kDir / "fifo2", to_fifo);
  expect_refused(to_fifo, "a FIFO (through a symbolic link)");
}

BOOST_AUTO_TEST_CASE(directory_outputs) {
  std::ofstream(kDir / "plain") << "x";
  BOOST_CHECK_THROW(jam::check_output_directory("out-dir", (kDir / "plain").string()),
                    jam::ConfigError);
  BOOST_CHECK_NO_THROW(jam::check_output_directory("out-dir", kDir.string()));
  BOOST_CHECK_NO_THROW(jam::check_output_directory("out-dir", (kDir / "new").string()));

  // A campaign whose output names a regular file: refused before any run, the file kept.
  const fs::path file = kDir / "c.toml";
  std::ofstream(file) << "name = \"c\"\ndim = 2\nsizes = [64]\nphi_init = [0.7]\n"
                         "log10_rates = [-2.5]\nsamples = 1\nphi_stop = 0.72\nseed = 1\n"
                         "output = \""
                      << (kDir / "plain").string() << "\"\n";
  const Outcome o =
      jam::test::run_jam_logged(kDir / "log.txt", "campaign run --quiet " + file.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(o.output.find("output " + (kDir / "plain").string() + ": is a regular file") !=
                 std::string::npos,
             o.output);
  BOOST_TEST(jam::test::slurp(kDir / "plain") == "x");
}

BOOST_AUTO_TEST_SUITE_END()
