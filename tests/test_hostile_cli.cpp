// What an attacker tried against the command line, one test per reproduction: a file set aside
// is never overwritten, an MPI rank that is refused ends the others, FIFOs never make jam wait,
// SIGTERM ends a run with its checkpoint, --write-start is checked before any work, names the
// file system cannot hold are refused up front, the LAMMPS importer refuses what would make a
// corrupt run, and grids are bounded before they are allocated. Every jam started here runs
// under `timeout`, so that a regression to a hang fails the test instead of CI.
#include <sys/stat.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "file_faults.hpp"
#include "process.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;
using jam::test::Outcome;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-hostile-" + std::to_string(::getpid()));

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

/// `jam <args>` killed after `seconds` (exit status 137 then): a hang fails, it does not wait.
Outcome jam_within(int seconds, const std::string& args) {
  std::vector<std::string> argv = {"timeout", "-s", "KILL", std::to_string(seconds)};
  for (auto& w : jam::test::jam_argv(args)) argv.push_back(w);
  return jam::test::run_logged(kDir / "log.txt", argv);
}

bool mentions(const Outcome& o, const std::string& text) {
  return o.output.find(text) != std::string::npos;
}

std::size_t lines(const Outcome& o) {
  return static_cast<std::size_t>(std::count(o.output.begin(), o.output.end(), '\n'));
}

const std::string kSim =
    "sim --quiet --n 64 --phi-init 0.7 --phi-stop 0.72 --rate 1e-2 --phi-step 0.005 ";

void write(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
}

fs::path small_campaign(const std::string& name) {
  const fs::path file = kDir / (name + ".toml");
  write(file, "name = \"" + name +
                  "\"\ndim = 2\nsizes = [64]\nphi_init = [0.7]\nlog10_rates = [-2]\nsamples = 1\n"
                  "phi_stop = 0.72\nphi_step = 0.005\nseed = 1\noutput = \"" +
                  (kDir / name).string() + "\"\n");
  return file;
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(hostile_cli, Fixture)

BOOST_AUTO_TEST_CASE(a_second_foreign_file_does_not_replace_the_first_rejected) {
  const fs::path file = small_campaign("aside");
  BOOST_REQUIRE(jam_within(120, "campaign run --quiet " + file.string()).status == 0);
  const fs::path run = kDir / "aside" / "runs" / "n64_phi0.7000_r-2.00_s000.h5";
  BOOST_REQUIRE(fs::exists(run));
  for (const char* text : {"first foreign file\n", "second foreign file\n"}) {
    write(run, text);
    BOOST_TEST(jam_within(120, "campaign run --quiet " + file.string()).status == 0);
  }
  BOOST_TEST(jam::test::slurp(run.string() + ".rejected") == "first foreign file\n");
  BOOST_TEST(jam::test::slurp(run.string() + ".rejected.1") == "second foreign file\n");
  const Outcome status = jam_within(60, "campaign status " + (kDir / "aside").string());
  BOOST_TEST(status.status == 0, status.output);  // the set-aside files are not runs
}

BOOST_AUTO_TEST_CASE(mpi_rank_0_refused_ends_rank_1_too) {
  if (jam::find_program("mpirun").empty()) {
    BOOST_TEST_MESSAGE("mpirun not installed: skipped");
    return;
  }
  // Rank 0 is refused before the first collective ("refusing to mix runs": the directory was
  // run with another seed); rank 1 used to wait in MPI_Barrier for ever.
  const fs::path file = small_campaign("mixed");
  BOOST_REQUIRE(jam_within(120, "campaign run --quiet " + file.string()).status == 0);
  std::string text = jam::test::slurp(file);
  text.replace(text.find("seed = 1"), 8, "seed = 2");
  write(file, text);
  std::vector<std::string> argv = {
      "timeout",         "-s",  "KILL", "60", "mpirun", "--allow-run-as-root",
      "--oversubscribe", "-np", "2"};
  for (auto& w : jam::test::jam_argv("campaign run --quiet " + file.string())) argv.push_back(w);
  const Outcome o = jam::test::run_logged(kDir / "mpi.txt", argv);
  if (mentions(o, "built without MPI")) {
    BOOST_TEST_MESSAGE("jam built without MPI: skipped");
    return;
  }
  BOOST_TEST(o.status == 2, o.output);  // as without MPI, not 137 (killed by timeout)
  BOOST_TEST(mentions(o, "refusing to mix runs"), o.output);
}

BOOST_AUTO_TEST_CASE(fifo_at_run_h5_checkpoint_refused_not_waited_on) {
  const fs::path out = kDir / "run.h5";
  BOOST_REQUIRE(::mkfifo((out.string() + ".checkpoint").c_str(), 0600) == 0);
  const Outcome o = jam_within(60, kSim + "--out " + out.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, "checkpoint " + out.string() + ".checkpoint: is a FIFO"), o.output);
  BOOST_TEST(fs::is_fifo(out.string() + ".checkpoint"));  // left alone
  BOOST_TEST(!fs::exists(out));
}

BOOST_AUTO_TEST_CASE(fifo_read_start_refused_not_waited_on) {
  const fs::path start = kDir / "start.h5";
  BOOST_REQUIRE(::mkfifo(start.c_str(), 0600) == 0);
  const Outcome o = jam_within(
      60, kSim + "--relax 0 --read-start " + start.string() + " --out " + (kDir / "r.h5").string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, "--read-start " + start.string()), o.output);
  BOOST_TEST(mentions(o, "FIFO"), o.output);
  BOOST_TEST(lines(o) == 1u, o.output);
}

// A LAMMPS log or data file that is a FIFO: refused in one line naming it, before it is
// opened (an open would wait for a writer for ever), and left where it is.
BOOST_AUTO_TEST_CASE(fifo_lammps_log_and_data_refused_not_waited_on) {
  const fs::path log = kDir / "lammps.log", data = kDir / "start.data";
  BOOST_REQUIRE(::mkfifo(log.c_str(), 0600) == 0);
  const std::string out = " --out " + (kDir / "imported.h5").string();
  Outcome o = jam_within(60, "import lammps " + log.string() + out +
                                 " --column pressure=Press --column volume=Volume"
                                 " --rate 1e-3 --diameter-ratio 1.4 --sample 0");
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, log.string()), o.output);
  BOOST_TEST(mentions(o, "FIFO"), o.output);
  BOOST_TEST(lines(o) == 1u, o.output);
  // The bundled input's route: a stored log that imports with its stored data file.
  BOOST_REQUIRE(::mkfifo(data.c_str(), 0600) == 0);
  const fs::path ref = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps" / "inertial-2d";
  o = jam_within(
      60, "import lammps " + (ref / "lammps.log").string() + out + " --data " + data.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, data.string()), o.output);
  BOOST_TEST(mentions(o, "FIFO"), o.output);
  BOOST_TEST(lines(o) == 1u, o.output);
  BOOST_TEST(fs::is_fifo(log));
  BOOST_TEST(fs::is_fifo(data));
  BOOST_TEST(!fs::exists(kDir / "imported.h5"));
}

// checks.json as a FIFO where a verdict file is read (here the scatter model of `campaign plan
// --scatter-from DIR`): refused in one line naming it, not waited on, and left where it is.
BOOST_AUTO_TEST_CASE(fifo_checks_json_refused_not_waited_on) {
  const fs::path dir = kDir / "fifo-checks", checks = dir / "checks.json";
  fs::create_directories(dir);
  BOOST_REQUIRE(::mkfifo(checks.c_str(), 0600) == 0);
  const Outcome o = jam_within(
      60, "campaign plan " + small_campaign("plan").string() + " --scatter-from " + dir.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, checks.string() + ": is a FIFO"), o.output);
  BOOST_TEST(lines(o) == 1u, o.output);
  BOOST_TEST(fs::is_fifo(checks));
}

BOOST_AUTO_TEST_CASE(fifos_named_like_a_pending_run_and_its_record_do_not_hang_the_campaign) {
  const fs::path file = small_campaign("fifo");
  const fs::path runs = kDir / "fifo" / "runs";
  fs::create_directories(runs);
  BOOST_REQUIRE(::mkfifo((runs / "n64_phi0.7000_r-2.00_s000.record").c_str(), 0600) == 0);
  const Outcome status = jam_within(60, "campaign status " + (kDir / "fifo").string());
  BOOST_TEST(status.status != 137, "campaign status hung on a FIFO record");
  Outcome run = jam_within(120, "campaign run --quiet " + file.string());
  BOOST_TEST(run.status == 2, run.output);
  BOOST_TEST(mentions(run, "is a FIFO"), run.output);
  fs::remove(runs / "n64_phi0.7000_r-2.00_s000.record");
  BOOST_REQUIRE(::mkfifo((runs / "n64_phi0.7000_r-2.00_s000.h5").c_str(), 0600) == 0);
  for (const std::string& args : {"campaign status " + (kDir / "fifo").string(),
                                  "stats --no-fit " + (kDir / "fifo").string()}) {
    BOOST_TEST(jam_within(60, args).status != 137, args << " hung on a FIFO run file");
  }
  run = jam_within(120, "campaign run --quiet " + file.string());
  BOOST_TEST(run.status != 137, run.output);
  // The FIFO is set aside like any file that is not the run's result, never deleted.
  BOOST_TEST(fs::is_fifo(runs / "n64_phi0.7000_r-2.00_s000.h5.rejected"));
}

BOOST_AUTO_TEST_CASE(sigterm_ends_a_large_run_with_its_checkpoint) {
  // N = 2^18 in 2D: 256 steps take seconds, so the stop must come between single steps.
  const fs::path out = kDir / "large.h5";
  const pid_t pid = jam::test::spawn_jam(
      "sim --quiet --n 262144 --phi-init 0.8 --phi-stop 0.84 --rate 1e-4 --out " + out.string());
  ::sleep(3);
  const auto sent = std::chrono::steady_clock::now();
  ::kill(pid, SIGTERM);
  const int status = jam::test::wait_for(pid);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  BOOST_TEST_MESSAGE("SIGTERM to exit: " << seconds << " s");  // measured, not asserted
  BOOST_TEST(status == 130);
  BOOST_TEST(fs::exists(out.string() + ".checkpoint"));
  BOOST_TEST(!fs::exists(out));
}

// Slurm at a time limit sends SIGTERM to every process of the job step, and the batch script
// forwards its own: two signals together are one request, and the run still leaves its
// checkpoint (a second signal ended jam at once, losing the run's progress).
BOOST_AUTO_TEST_CASE(two_sigterms_together_still_leave_the_checkpoint) {
  const fs::path out = kDir / "twice.h5";
  const pid_t pid = jam::test::spawn_jam(
      "sim --quiet --n 262144 --phi-init 0.8 --phi-stop 0.84 --rate 1e-4 --out " + out.string());
  ::sleep(3);
  ::kill(pid, SIGTERM);
  // 5 ms later: delivered apart (two pending SIGTERMs would merge into one), and before the
  // checkpoint is written (0.02-0.05 s at this N).
  ::usleep(5000);
  ::kill(pid, SIGTERM);
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  BOOST_TEST(fs::exists(out.string() + ".checkpoint"));
  BOOST_TEST(!fs::exists(out));
}

BOOST_AUTO_TEST_CASE(sigterm_during_the_jamming_point_search_stops_and_resumes_bitwise) {
  // N = 1024 from 0.82 at rate 1e-2: the compression takes 0.3 s, the search for phi_Ji about
  // 5 s of FIRE minimizations, which used to run to the end whatever the signal said.
  const std::string run =
      "sim --quiet --n 1024 --phi-init 0.82 --phi-stop 0.86 --rate 1e-2 --jamming-point --out ";
  const fs::path whole = kDir / "whole.h5", stopped = kDir / "stopped.h5";
  BOOST_REQUIRE(jam_within(300, run + whole.string()).status == 0);
  const pid_t pid = jam::test::spawn_jam(run + stopped.string());
  ::sleep(2);
  ::kill(pid, SIGTERM);
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  BOOST_TEST(fs::exists(stopped.string() + ".checkpoint"));
  BOOST_REQUIRE(jam_within(300, run + stopped.string()).status == 0);
  BOOST_TEST((jam::test::slurp(whole) == jam::test::slurp(stopped)));
}

BOOST_AUTO_TEST_CASE(write_start_fifo_device_symlink_dangling_directory_refused_before_work) {
  const std::string chain = "--write-start-at 0.71 --out " + (kDir / "w.h5").string();
  const fs::path fifo = kDir / "fifo", dangling = kDir / "dangling", link = kDir / "link";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  fs::create_symlink(kDir / "nowhere", dangling);
  fs::create_directories(kDir / "dir");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {fifo.string(), "is a FIFO"},
      {"/dev/null", "is a character device"},
      {dangling.string(), "is a symbolic link to a missing file"},
      {(kDir / "dir").string(), "is a directory"},
      {(kDir / "missing" / "start.h5").string(), "cannot write there"},
  };
  for (const auto& [path, why] : cases) {
    const Outcome o = jam_within(60, kSim + "--write-start " + path + " " + chain);
    BOOST_TEST_CONTEXT(path) {
      BOOST_TEST(o.status == 2, o.output);
      BOOST_TEST(mentions(o, "--write-start " + path + ": " + why), o.output);
      BOOST_TEST(lines(o) == 1u, o.output);
      BOOST_TEST(!fs::exists(kDir / "w.h5"));  // refused before the run, not after it
    }
  }
  BOOST_TEST(fs::is_fifo(fifo));
  // A link to a regular file is written through: the link stays, its target is the start.
  write(kDir / "target.h5", "old");
  fs::create_symlink(kDir / "target.h5", link);
  const Outcome o = jam_within(60, kSim + "--write-start " + link.string() + " " + chain);
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(fs::is_symlink(link));
  BOOST_TEST(jam::test::slurp(kDir / "target.h5") != "old");
}

BOOST_AUTO_TEST_CASE(symlinked_stats_h5_and_checks_json_written_through_fifos_refused) {
  const fs::path file = small_campaign("links");
  const fs::path dir = kDir / "links";
  BOOST_REQUIRE(jam_within(120, "campaign run --quiet " + file.string()).status == 0);
  // Links to regular files elsewhere: written through, the links stay (docs/cli.md).
  write(kDir / "stats-target.h5", "old");
  write(kDir / "checks-target.json", "old");
  fs::create_symlink(kDir / "stats-target.h5", dir / "stats.h5");
  fs::create_symlink(kDir / "checks-target.json", dir / "checks.json");
  BOOST_TEST(jam_within(60, "stats --no-fit " + dir.string()).status == 0);
  jam_within(120, "check all --no-lmp " + dir.string());
  BOOST_TEST(fs::is_symlink(dir / "stats.h5"));
  BOOST_TEST(fs::is_symlink(dir / "checks.json"));
  BOOST_TEST(jam::test::slurp(kDir / "stats-target.h5") != "old");
  BOOST_TEST(jam::test::slurp(kDir / "checks-target.json").find("verdicts") != std::string::npos);
  // FIFOs: refused before the work, and left as they are.
  fs::remove(dir / "checks.json");
  BOOST_REQUIRE(::mkfifo((dir / "checks.json").c_str(), 0600) == 0);
  Outcome o = jam_within(60, "check all --no-lmp " + dir.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, (dir / "checks.json").string() + ": is a FIFO"), o.output);
  BOOST_TEST(fs::is_fifo(dir / "checks.json"));
  fs::remove(dir / "stats.h5");
  BOOST_REQUIRE(::mkfifo((dir / "stats.h5").c_str(), 0600) == 0);
  o = jam_within(60, "stats --no-fit " + dir.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, (dir / "stats.h5").string() + ": is a FIFO"), o.output);
  BOOST_TEST(fs::is_fifo(dir / "stats.h5"));
}

BOOST_AUTO_TEST_CASE(out_name_of_230_characters_refused_before_the_first_checkpoint) {
  const fs::path out = kDir / (std::string(230, 'a') + ".h5");
  const Outcome o = jam_within(60, kSim + "--out " + out.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, "a file name of 233 characters is too long"), o.output);
  BOOST_TEST(lines(o) == 1u, o.output);
  const fs::path fits = kDir / (std::string(200, 'a') + ".h5");
  BOOST_TEST(jam_within(60, kSim + "--out " + fits.string()).status == 0);
}

BOOST_AUTO_TEST_CASE(import_lammps_refuses_what_would_make_a_corrupt_run) {
  const fs::path ref = fs::path(JAM_SOURCE_DIR) / "reference" / "lammps" / "inertial-2d";
  const std::string log = jam::test::slurp(ref / "lammps.log");
  const std::string data = " --data " + (ref / "start.data").string();
  const fs::path out = kDir / "imported.h5";
  BOOST_REQUIRE(jam_within(60, "import lammps " + (ref / "lammps.log").string() + data + " --out " +
                                   out.string())
                    .status == 0);
  fs::remove(out);
  // (pattern in the log, replacement, what the one-line error must say)
  const std::vector<std::array<std::string, 3>> cases = {
      {"\n      50 0.25 0.00064328635532286225", "\n      50 0.25 nan",
       "c_virial nan is not finite"},
      {"\n      50 0.25 0.00064328635532286225", "\n      50 -0.25 0.00064328635532286225",
       "times must increase"},
      {"\n      50 0.25 0.00064328635532286225", "\n      50 inf 0.00064328635532286225",
       "Time inf is not finite"},
      {"\ntimestep        0.0050000000000000001", "\ntimestep        inf",
       "timestep inf is not finite"},
      {"x trate -0.001 y trate -0.001 remap x", "x trate -1e308 y trate -1e308 remap x",
       "trate -1e308 (must be a compression"},
      {"\n      50 0.25 0.00064328635532286225", "\n      50 0.25 0.5abc",
       "c_virial '0.5abc' is not a number"},
  };
  for (const auto& [from, to, says] : cases) {
    std::string bad = log;
    const auto at = bad.find(from);
    BOOST_REQUIRE(at != std::string::npos);
    bad.replace(at, from.size(), to);
    write(kDir / "bad.log", bad);
    const Outcome o = jam_within(
        60, "import lammps " + (kDir / "bad.log").string() + data + " --out " + out.string());
    BOOST_TEST_CONTEXT(to) {
      BOOST_TEST(o.status == 2, o.output);
      BOOST_TEST(mentions(o, says), o.output);
      BOOST_TEST(lines(o) == 1u, o.output);
      BOOST_TEST(!fs::exists(out));
    }
  }
}

BOOST_AUTO_TEST_CASE(stats_z_step_1e_minus_7_refused_before_allocating) {
  const Outcome o = jam_within(60, "stats --z-step 1e-7 " + kDir.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(mentions(o, "--z-step 1e-07: must be in [1e-4, 1]"), o.output);
}

// A full disk during `jam check all`: the error says "No space left on device" and names the
// file, no truncated copy is left under a final name, and a summary printed to a file on the
// full disk is an error, not exit 0. Root only (a tmpfs is mounted); skipped otherwise.
BOOST_AUTO_TEST_CASE(full_disk_during_check_all_names_the_file_and_leaves_no_truncated_copy) {
  const jam::test::SmallTmpfs tmpfs(kDir / "mnt", "1m");
  if (!tmpfs.mounted) {
    BOOST_TEST_MESSAGE("skipped: mounting a tmpfs needs root");
    return;
  }
  const fs::path& mnt = tmpfs.dir;
  const fs::path file = small_campaign("full");
  std::string text = jam::test::slurp(file);
  text.replace(text.find((kDir / "full").string()), (kDir / "full").string().size(),
               (mnt / "full").string());
  write(file, text);
  BOOST_REQUIRE(jam_within(120, "campaign run --quiet " + file.string()).status == 0);
  BOOST_REQUIRE(jam_within(60, "stats --no-fit " + (mnt / "full").string()).status == 0);
  // Filled up, then a few kB given back: each leaves the disk full at another write (the copy
  // of a start, a LAMMPS data file written by fmt, an HDF5 file). A full tmpfs can answer EIO;
  // it is still named for what it is.
  for (const int kilobytes : {0, 4, 12, 24, 40}) {
    fs::remove_all(mnt / "full" / "lammps-check");
    tmpfs.empty();
    tmpfs.fill(1024u * kilobytes);
    // --with-lammps: the self-checks write LAMMPS data files, one more write to fail.
    const Outcome o =
        jam_within(120, "check all --no-lmp --with-lammps " + (mnt / "full").string());
    BOOST_TEST_CONTEXT(kilobytes << " kB free") {
      BOOST_TEST(o.status == 2, o.output);
      BOOST_TEST(mentions(o, "No space left on device"), o.output);
      BOOST_TEST(mentions(o, (mnt / "full").string()), o.output);  // names the file
      for (const auto& e : fs::recursive_directory_iterator(mnt / "full")) {
        if (e.is_regular_file())
          BOOST_TEST(fs::file_size(e.path()) > 0u, "truncated: " << e.path());
      }
    }
  }
  fs::remove_all(mnt / "full" / "lammps-check");
  tmpfs.fill();
  std::vector<std::string> argv = jam::test::jam_argv("campaign status " + (mnt / "full").string());
  jam::ProcessOptions po;
  po.stdout_file = (mnt / "status.txt").string();
  po.stderr_file = (kDir / "status-err.txt").string();
  BOOST_TEST(jam::run_program(argv, po) == 2);
  BOOST_TEST(mentions({2, jam::test::slurp(kDir / "status-err.txt")},
                      "cannot write to standard output: No space left on device"));
}

BOOST_AUTO_TEST_SUITE_END()
