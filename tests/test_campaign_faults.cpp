// Faults in a campaign directory, through the executable: run files corrupted in their data
// (one flipped bit), truncated or without their `complete` attribute are detected, listed by
// `campaign status`, left out of `jam stats` with a warning, and redone identically by `campaign
// run`; a run whose time step is unstable is marked failed with the error while the others finish;
// a full disk and an unwritable directory give a clear error and leave earlier results intact; 1
// and 2 threads give identical run files.
#include <hdf5.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "file_faults.hpp"
#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/run_file.hpp"

namespace fs = std::filesystem;
using jam::test::flip_bit_of;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-faults-" + std::to_string(::getpid()));

using jam::test::Outcome;

/// Runs `jam <args>` (no shell) under `limits`.
Outcome run_jam(const std::string& args, const jam::test::Limits& limits = {}) {
  return jam::test::run_jam_logged(kDir / "output.txt", args, limits);
}

fs::path write_campaign(const std::string& name, const std::string& body, const fs::path& out) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << body << "output = \"" << out.string() << "\"\n";
  return file;
}

std::map<std::string, std::string> run_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    if (e.path().extension() == ".h5") files[e.path().filename().string()] = slurp(e.path());
  }
  return files;
}

const std::string kTiny = R"(name = "tiny"
dim = 2
sizes = [64]
phi_init = [0.70]
log10_rates = [-2.0]
samples = 3
phi_stop = 0.86
phi_step = 0.002
dt = 0.02
relax_energy = "1e-14"
seed = 3
)";

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

}  // namespace

BOOST_FIXTURE_TEST_SUITE(faults, Fixture)

BOOST_AUTO_TEST_CASE(corrupt_run_files_are_detected_left_out_and_redone) {
  const fs::path dir = kDir / "c";
  std::string text = kTiny;
  text.replace(text.find("samples = 3"), 11, "samples = 4");
  const fs::path file = write_campaign("c", text, dir);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const auto first = run_files(dir);
  BOOST_REQUIRE(first.size() == 4u);
  for (const auto& [name, bytes] : first)
    BOOST_TEST(jam::run_file_problem((dir / "runs" / name).string()) == "");

  // One bit of one pressure value: the HDF5 file still opens and looks complete.
  const fs::path flipped = dir / "runs" / "n64_phi0.7000_r-2.00_s001.h5";
  const double p3 = jam::h5::File::open_read(flipped.string()).read_dataset("pressure")[3];
  BOOST_REQUIRE(flip_bit_of(flipped, p3));
  BOOST_TEST(jam::run_file_problem(flipped.string()).find("checksum") != std::string::npos);
  // Truncated to a tenth.
  const fs::path truncated = dir / "runs" / "n64_phi0.7000_r-2.00_s002.h5";
  fs::resize_file(truncated, fs::file_size(truncated) / 10);
  // Its `complete` attribute deleted: every value intact, the file no longer says it ended.
  const fs::path unfinished = dir / "runs" / "n64_phi0.7000_r-2.00_s003.h5";
  const hid_t f = H5Fopen(unfinished.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  BOOST_REQUIRE(f >= 0);
  BOOST_REQUIRE(H5Adelete(f, "complete") >= 0);
  BOOST_REQUIRE(H5Fclose(f) >= 0);
  BOOST_TEST(jam::run_file_problem(unfinished.string()).find("incomplete") != std::string::npos);

  Outcome o = run_jam("campaign status " + dir.string());
  BOOST_TEST(o.output.find("corrupt  3") != std::string::npos, o.output);
  BOOST_TEST(o.output.find("corrupt n64_phi0.7000_r-2.00_s003: run file is incomplete") !=
                 std::string::npos,
             o.output);
  BOOST_TEST(o.output.find("corrupt n64_phi0.7000_r-2.00_s001: checksum") != std::string::npos,
             o.output);
  BOOST_TEST(o.output.find("n64_phi0.7000_r-2.00_s002") != std::string::npos, o.output);

  o = run_jam("stats " + dir.string());
  BOOST_TEST(o.output.find("1 runs averaged, 3 skipped") != std::string::npos, o.output);
  BOOST_TEST(
      o.output.find("warning: corrupt run n64_phi0.7000_r-2.00_s001 left out") != std::string::npos,
      o.output);

  o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST((run_files(dir) == first));  // redone bit for bit
}

// dt = 0.45 is inside the stability bound of the sparse start at phi_init 0.3 and of the
// packings it is compressed through up to phi 0.75, but not of the random start at 0.74 (its
// overlaps make lambda_max about 4.2 to 5, measured, so 1.9/lambda_max < 0.45).
BOOST_AUTO_TEST_CASE(unstable_run_fails_alone) {
  const fs::path dir = kDir / "u";
  std::string text = kTiny;
  text.replace(text.find("phi_init = [0.70]"), 17, "phi_init = [0.30, 0.74]");
  text.replace(text.find("phi_stop = 0.86"), 15, "phi_stop = 0.75");
  // Heun, whose step is dt: the Chebyshev integrator is stable at any first step.
  text.replace(text.find("dt = 0.02"), 9, "dt = 0.45\nintegrator = \"heun\"");
  text.replace(text.find("samples = 3"), 11, "samples = 1");
  // A step of dt 0.45 at rate 1e-2 compresses by 0.0068: output every 0.01, not 0.002.
  text.replace(text.find("phi_step = 0.002"), 16, "phi_step = 0.010");
  const fs::path file = write_campaign("u", text, dir);
  const Outcome o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST(o.status == 1, o.output);
  BOOST_TEST(o.output.find("run n64_phi0.7400_r-2.00_s000 failed: --dt 0.45: unstable") !=
                 std::string::npos,
             o.output);
  BOOST_TEST(!fs::exists(dir / "runs" / "n64_phi0.7400_r-2.00_s000.h5"));
  BOOST_TEST(jam::run_file_problem((dir / "runs" / "n64_phi0.3000_r-2.00_s000.h5").string()) == "");
  const Outcome status = run_jam("campaign status " + dir.string());
  BOOST_TEST(status.output.find("failed n64_phi0.7400_r-2.00_s000: --dt 0.45: unstable") !=
                 std::string::npos,
             status.output);
  BOOST_TEST(status.output.find("done     1") != std::string::npos, status.output);
}

namespace {

/// Earlier results, then more samples with the output made to fail by `limits`: a non-zero
/// exit, an error that says what failed, no crash, and the earlier run files unchanged.
/// Returns the failing invocation's outcome (its summary included: no --quiet).
Outcome earlier_results_survive(const fs::path& dir, const jam::test::Limits& limits,
                                const std::string& expected_error) {
  const fs::path file = write_campaign("f", kTiny, dir);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const auto first = run_files(dir);
  std::string more = kTiny;
  more.replace(more.find("samples = 3"), 11, "samples = 6");
  const fs::path bigger = write_campaign("f", more, dir);
  const Outcome o = run_jam("campaign run " + bigger.string(), limits);
  BOOST_TEST(o.status != 0, o.output);
  BOOST_TEST(o.output.find(expected_error) != std::string::npos, o.output);
  BOOST_TEST(o.output.find("Segmentation") == std::string::npos, o.output);
  auto now = run_files(dir);
  for (const auto& [name, bytes] : first) BOOST_TEST((now[name] == bytes), name);
  for (const auto& [name, bytes] : now) {
    BOOST_TEST(jam::run_file_problem((dir / "runs" / name).string()) == "", name);
  }
  return o;
}

}  // namespace

// A file-size limit (RLIMIT_FSIZE of 4 kB, SIGXFSZ ignored) makes every larger write fail
// with EFBIG, as a full disk does with ENOSPC, without privileges: the campaign file, records
// and manifest fit, a relaxed start or run file does not. The runs that could not write are
// not marked failed, so the same command finishes them once the space is back.
BOOST_AUTO_TEST_CASE(file_size_limit_like_a_full_disk) {
  const fs::path dir = kDir / "limit";
  // HDF5 keeps the memory of a file whose writes and close failed (its free lists and cache:
  // the library offers no way to release a file it could not flush); the process ends at once,
  // but under LeakSanitizer (scripts/sanitize.sh) that exit status would replace jam's. Leak
  // detection is off for this one invocation, so that the status is jam's.
  const char* asan = std::getenv("ASAN_OPTIONS");
  const std::string kept = asan ? asan : "";
  ::setenv("ASAN_OPTIONS", (kept + ":detect_leaks=0").c_str(), 1);
  const Outcome o = earlier_results_survive(dir, {4096}, "could not write its output");
  asan ? ::setenv("ASAN_OPTIONS", kept.c_str(), 1) : ::unsetenv("ASAN_OPTIONS");
  // Counted apart from failed runs, and exit 2 (a fault of the machine, not of a run): the
  // one or two runs under way when the first write failed, none started after it.
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(o.output.find(", 0 failed, ") != std::string::npos, o.output);
  BOOST_TEST(
      o.output.find(" could not write their output (run again to redo them)") != std::string::npos,
      o.output);
  BOOST_TEST(run_jam("campaign run --quiet " + (kDir / "f.toml").string()).status == 0);
  BOOST_TEST(run_files(dir).size() == 6u);
}

// A real full disk: a 512 kB tmpfs holding the campaign, filled up before the new runs. Needs
// root (mount); skipped with a message otherwise.
BOOST_AUTO_TEST_CASE(full_tmpfs) {
  const jam::test::SmallTmpfs tmpfs(kDir / "mnt", "512k");
  if (!tmpfs.mounted) {
    BOOST_TEST_MESSAGE("full_tmpfs skipped: mounting a tmpfs needs root");
    return;
  }
  const fs::path& mnt = tmpfs.dir;
  const fs::path dir = mnt / "campaign";
  const fs::path file = write_campaign("f", kTiny, dir);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const auto first = run_files(dir);
  tmpfs.fill(8192);  // leaving a few kB
  std::string more = kTiny;
  more.replace(more.find("samples = 3"), 11, "samples = 6");
  const fs::path bigger = write_campaign("f", more, dir);
  const Outcome o = run_jam("campaign run --quiet " + bigger.string());
  BOOST_TEST(o.status != 0, o.output);
  BOOST_TEST(o.output.find("jam") != std::string::npos, o.output);
  auto now = run_files(dir);
  for (const auto& [name, bytes] : first) BOOST_TEST((now[name] == bytes), name);
  for (const auto& [name, bytes] : now) {
    BOOST_TEST(jam::run_file_problem((dir / "runs" / name).string()) == "", name);
  }
  tmpfs.empty();
  const Outcome again = run_jam("campaign run --quiet " + bigger.string());
  BOOST_TEST(again.status == 0, again.output);
  BOOST_TEST(run_files(dir).size() == 6u);
}

// An unwritable runs/ directory: chmod when not root; as root (chmod does not stop root) a
// read-only tmpfs, or skipped with a message when mounting is not allowed either.
BOOST_AUTO_TEST_CASE(unwritable_directory) {
  const fs::path dir = kDir / "ro";
  const fs::path file = write_campaign("f", kTiny, dir);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const auto first = run_files(dir);
  std::string more = kTiny;
  more.replace(more.find("samples = 3"), 11, "samples = 6");
  const fs::path bigger = write_campaign("f", more, dir);
  bool restore_mode = false, unmount = false;
  if (::geteuid() != 0) {
    fs::permissions(dir / "runs", fs::perms::owner_write, fs::perm_options::remove);
    fs::permissions(dir, fs::perms::owner_write, fs::perm_options::remove);
    restore_mode = true;
  } else if (::mount((dir).c_str(), (dir).c_str(), nullptr, MS_BIND, nullptr) == 0 &&
             ::mount(nullptr, (dir).c_str(), nullptr, MS_BIND | MS_REMOUNT | MS_RDONLY, nullptr) ==
                 0) {
    unmount = true;
  } else {
    BOOST_TEST_MESSAGE("unwritable_directory skipped: root, and no read-only bind mount");
    return;
  }
  const Outcome o = run_jam("campaign run --quiet " + bigger.string());
  if (restore_mode) {
    fs::permissions(dir, fs::perms::owner_write, fs::perm_options::add);
    fs::permissions(dir / "runs", fs::perms::owner_write, fs::perm_options::add);
  }
  if (unmount) ::umount2(dir.c_str(), MNT_DETACH);
  BOOST_TEST(o.status != 0, o.output);
  BOOST_TEST(o.output.find("jam: error:") != std::string::npos, o.output);
  BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') <= 2, o.output);
  BOOST_TEST((run_files(dir) == first));
}

// Determinism across threads: each run is computed by one thread from its own seed, so the
// run files of a campaign are bitwise the same with 1 and 2 threads (MPI ranks against
// threads: test_campaign_end_to_end).
BOOST_AUTO_TEST_CASE(one_and_two_threads_give_identical_run_files) {
  std::string text = kTiny;
  text.replace(text.find("sizes = [64]"), 12, "sizes = [64, 96]");
  const fs::path one = write_campaign("one", text, kDir / "one");
  const fs::path two = write_campaign("two", text, kDir / "two");
  BOOST_REQUIRE(run_jam("campaign run --quiet --jobs 1 " + one.string()).status == 0);
  BOOST_REQUIRE(run_jam("campaign run --quiet --jobs 2 " + two.string()).status == 0);
  BOOST_TEST(run_files(kDir / "one").size() == 6u);
  BOOST_TEST((run_files(kDir / "one") == run_files(kDir / "two")));
}

BOOST_AUTO_TEST_SUITE_END()

// `jam check` and `jam stats` fail in one line, exit status 2, naming the file and the cause:
// a stats.h5 of random bytes, and a disk that fills up while the verdicts are written ("No
// space left on device", not "Input/output error"), leaving no verdict file behind.
BOOST_FIXTURE_TEST_CASE(check_fails_in_one_line, Fixture) {
  const fs::path dir = kDir / "chk";
  BOOST_REQUIRE(
      run_jam("campaign run --quiet " + write_campaign("k", kTiny, dir).string()).status == 0);
  BOOST_REQUIRE(run_jam("stats --no-fit " + dir.string()).status == 0);
  const std::string stats = slurp(dir / "stats.h5");
  auto one_line = [](const Outcome& o) {
    return std::count(o.output.begin(), o.output.end(), '\n') == 1;
  };

  std::ofstream(dir / "stats.h5", std::ios::binary | std::ios::trunc) << std::string(4096, '\x5a');
  Outcome o = run_jam("check sample_pairs " + dir.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(one_line(o), o.output);
  BOOST_TEST(o.output.find((dir / "stats.h5").string()) != std::string::npos, o.output);

  const jam::test::SmallTmpfs tmpfs(kDir / "mnt-check", "256k");
  if (!tmpfs.mounted) {
    BOOST_TEST_MESSAGE("full disk part skipped: mounting a tmpfs needs root");
    return;
  }
  const fs::path& mnt = tmpfs.dir;
  const fs::path full = mnt / "c";
  fs::create_directories(full);
  std::ofstream(full / "stats.h5", std::ios::binary) << stats;
  tmpfs.fill();
  o = run_jam("check sample_pairs " + full.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(o.output.find("No space left on device") != std::string::npos, o.output);
  BOOST_TEST(o.output.find("jam: error:") != std::string::npos, o.output);
  for (const auto& e : fs::directory_iterator(full)) {
    BOOST_TEST((e.path().filename() == "stats.h5"), "left behind: " << e.path());
  }
}

// `jam campaign status DIR` resolves the runs against DIR from any working directory (here /,
// with a campaign whose output was given relative to another directory), and its exit status
// says what it found: 0 all done, 4 missing, 1 corrupt; --json carries the same.
BOOST_FIXTURE_TEST_CASE(status_from_anywhere_and_its_exit_status, Fixture) {
  const fs::path dir = kDir / "st";
  fs::create_directories(dir);
  const fs::path file = dir / "c.toml";
  std::ofstream(file) << kTiny << "output = \"rel\"\n";  // relative to where it is run
  jam::ProcessOptions here;
  here.working_directory = dir;
  here.stdout_file = here.stderr_file = (kDir / "run.txt").string();
  BOOST_REQUIRE(
      jam::run_program({JAM_EXECUTABLE, "campaign", "run", "--quiet", file.string()}, here) == 0);
  auto status = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {JAM_EXECUTABLE, "campaign", "status", (dir / "rel").string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    jam::ProcessOptions root;
    root.working_directory = "/";
    root.stdout_file = root.stderr_file = (kDir / "status.txt").string();
    return Outcome{jam::run_program(argv, root), slurp(kDir / "status.txt")};
  };
  Outcome o = status({});
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(o.output.find("done     3") != std::string::npos, o.output);
  o = status({"--json"});
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(o.output.find("\"done\": 3") != std::string::npos, o.output);
  fs::remove(dir / "rel" / "runs" / "n64_phi0.7000_r-2.00_s000.h5");
  BOOST_TEST(status({}).status == 4);
  std::ofstream(dir / "rel" / "runs" / "n64_phi0.7000_r-2.00_s001.h5") << "not a run file";
  o = status({"--json"});
  BOOST_TEST(o.status == 1, o.output);
  BOOST_TEST(o.output.find("\"corrupt\": 1") != std::string::npos, o.output);
}
