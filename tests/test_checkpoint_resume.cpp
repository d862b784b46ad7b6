// A run killed (SIGKILL) at random moments and restarted, again and again, ends with a run
// file bitwise identical to an uninterrupted run, having resumed from checkpoints rather than
// from the start; SIGINT stops a run cleanly with a checkpoint (exit 130); a jamming-point
// search killed or stopped resumes from its last checkpointed decision.
#include <signal.h>

#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "process.hpp"
#include "sim/io/hdf5_file.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;
using jam::test::spawn_jam;
using jam::test::wait_for;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-resume-" + std::to_string(::getpid()));

// Runs `args` once uninterrupted and once killed `kills` times at random moments (checkpoints
// every 20 ms), then compares the two run files byte for byte. Each case's run takes about 2 s
// on one core here, so that the kills (150-700 ms after each attempt's first checkpoint) land
// mid-run.
void check_resume(const std::string& args, int kills, int signal_number, unsigned seed) {
  fs::create_directories(kDir);
  const fs::path ref = kDir / "ref.h5", resumed = kDir / "resumed.h5";
  fs::remove(ref);
  fs::remove(resumed);
  BOOST_TEST_REQUIRE(
      wait_for(spawn_jam("sim " + args + " --checkpoint-interval 0 --out " + ref.string())) == 0);

  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> delay_ms(150, 700);
  const std::string interrupted = args + " --checkpoint-interval 0.02 --out " + resumed.string();
  int checkpoints_seen = 0, finished_early = 0;
  for (int k = 0; k < kills; ++k) {
    // Signalled a random moment after it has written its first checkpoint (so its handlers are
    // in place however slow its start is on a loaded machine).
    const auto since = fs::file_time_type::clock::now();
    const pid_t pid = spawn_jam("sim " + interrupted);
    jam::test::wrote_since(kDir, since, pid);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    kill(pid, signal_number);
    const int status = wait_for(pid);
    if (status == 0) {
      ++finished_early;  // the run beat the signal: nothing to resume
      break;
    }
    if (signal_number == SIGINT) BOOST_TEST(status == 130);
    BOOST_TEST(!fs::exists(resumed));  // an interrupted run never leaves a run file
    checkpoints_seen += fs::exists(resumed.string() + ".checkpoint");
  }
  if (!finished_early) {
    // The last attempt must continue from the checkpoint, not start over: it says so.
    const bool had_checkpoint = fs::exists(resumed.string() + ".checkpoint");
    std::string loud = interrupted;
    loud.erase(loud.find(" --quiet"), 8);
    const fs::path log = kDir / "final.txt";
    BOOST_TEST_REQUIRE(jam::test::run_jam_logged(log, "sim " + loud).status == 0);
    if (had_checkpoint) {
      BOOST_TEST(slurp(log).find("resumed from checkpoint") != std::string::npos, slurp(log));
    }
  }
  BOOST_TEST(checkpoints_seen >= 1);  // the run really continued from checkpoints
  BOOST_TEST(!fs::exists(resumed.string() + ".checkpoint"));
  BOOST_TEST((slurp(ref) == slurp(resumed)), "resumed run differs from the uninterrupted one");
}

}  // namespace

BOOST_AUTO_TEST_CASE(euler_2d_killed_during_relaxation_and_compression) {
  check_resume(
      "--dim 2 --n 2048 --phi-init 0.6 --phi-stop 0.86 --rate 1e-3 --integrator euler --dt 0.01 "
      "--quiet --rattlers",
      4, SIGKILL, 1);
}

BOOST_AUTO_TEST_CASE(heun_3d_killed) {
  check_resume(
      "--dim 3 --n 4096 --phi-init 0.55 --phi-stop 0.68 --rate 2e-4 --integrator heun --quiet", 3,
      SIGKILL, 2);
}

// The adaptive integrator carries its next step and the accumulated time through checkpoints
// (relaxation and compression), with the Hertzian law.
BOOST_AUTO_TEST_CASE(chebyshev_hertzian_2d_killed) {
  check_resume(
      "--dim 2 --n 4096 --phi-init 0.8 --phi-stop 0.86 --rate 1e-6 --integrator chebyshev "
      "--contact hertzian --quiet",
      3, SIGKILL, 4);
}

// A chained start (--read-start, written by a faster run at 0.80) resumes like any start.
BOOST_AUTO_TEST_CASE(chained_start_killed) {
  fs::create_directories(kDir);
  const fs::path start = kDir / "chain.start.h5";
  BOOST_TEST_REQUIRE(
      wait_for(spawn_jam("sim --dim 2 --n 4096 --phi-init 0.7 --phi-stop 0.81 --rate 1e-3 "
                         "--write-start " +
                         start.string() +
                         " --write-start-at 0.8 --quiet "
                         "--out " +
                         (kDir / "parent.h5").string())) == 0);
  check_resume("--dim 2 --n 4096 --phi-stop 0.86 --rate 2e-6 --relax 0 --read-start " +
                   start.string() + " --quiet",
               3, SIGKILL, 5);
}

// An unrelaxed start at a fast rate: the start's transient at its own tolerance (the switch
// decided from the recorded points) and every output point from the continuous extension.
BOOST_AUTO_TEST_CASE(chebyshev_unrelaxed_dense_output_killed) {
  check_resume(
      // Rate 1e-5: about 2 s on a quiet core (at 1e-4, 0.6 s: every run beat its first kill).
      "--dim 2 --n 8192 --phi-init 0.75 --phi-stop 0.88 --phi-step 0.0005 --rate 1e-5 "
      "--relax 0 --quiet",
      3, SIGKILL, 6);
}

BOOST_AUTO_TEST_CASE(inertial_2d_killed_keeps_velocities) {
  check_resume(
      "--dim 2 --n 4096 --phi-init 0.7 --phi-stop 0.86 --rate 1e-3 --dynamics inertial "
      "--q 0.1 --dt 0.01 --relax-energy 1e-6 --quiet",
      3, SIGKILL, 3);
}

BOOST_AUTO_TEST_CASE(sigint_stops_cleanly_and_resumes) {
  // The default integrator (Chebyshev), whose tolerance differs between the relaxation (1e-4)
  // and the compression (auto: 100 rate within [1e-4, 3e-3], 5e-4 at this rate).
  // Rate 5e-6: about 1.7 s on a quiet core (at 2e-5, 0.7 s: the run beat the signal).
  check_resume("--dim 2 --n 4096 --phi-init 0.7 --phi-stop 0.86 --rate 5e-6 --quiet", 2, SIGINT, 4);
  fs::remove_all(kDir);
}

namespace {

/// The decisions of a jamming-point search in `checkpoint` (0 while there is none). jam
/// replaces a checkpoint by renaming, so a read is of one whole file.
std::size_t decisions_in(const fs::path& checkpoint) {
  try {
    return jam::h5::File::open_read(checkpoint.string()).read_dataset_u32("jamming_answers").size();
  } catch (const std::exception&) {
    return 0;
  }
}

/// Waits (at most two minutes) until `checkpoint` holds more than `than` decisions.
bool wait_for_decisions(const fs::path& checkpoint, std::size_t than) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (std::chrono::steady_clock::now() < deadline) {
    if (decisions_in(checkpoint) > than) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

}  // namespace

// The jamming-point search (about 15 FIRE minimizations after the compression, several
// seconds at N = 1024) killed (SIGKILL) and stopped (SIGTERM): its decisions are in the
// checkpoint (taken after each decision when due: every 20 ms here), each resumption replays
// them and goes on, and the run file is the uninterrupted run's byte for byte.
BOOST_AUTO_TEST_CASE(jamming_search_killed_and_stopped_resumes_from_its_decisions) {
  fs::create_directories(kDir);
  const std::string args =
      "sim --dim 2 --n 1024 --phi-init 0.8 --phi-stop 0.86 --rate 1e-3 --jamming-point "
      "--threads 1 --quiet --out ";
  const fs::path ref = kDir / "jp-ref.h5", resumed = kDir / "jp.h5";
  const fs::path checkpoint = resumed.string() + ".checkpoint";
  fs::remove(ref);
  fs::remove(resumed);
  fs::remove(checkpoint);
  BOOST_TEST_REQUIRE(wait_for(spawn_jam(args + ref.string() + " --checkpoint-interval 0")) == 0);
  const auto minimizations = static_cast<std::size_t>(
      jam::h5::File::open_read(ref.string()).read_attribute_int("jamming_minimizations"));
  const std::string interrupted = args + resumed.string() + " --checkpoint-interval 0.02";

  pid_t pid = spawn_jam(interrupted);
  BOOST_TEST_REQUIRE(wait_for_decisions(checkpoint, 1), "no decisions were checkpointed");
  kill(pid, SIGKILL);
  BOOST_TEST_REQUIRE(wait_for(pid) == -SIGKILL);
  const std::size_t killed_at = decisions_in(checkpoint);
  BOOST_TEST(killed_at >= 2u);

  pid = spawn_jam(interrupted);  // replays them and decides further
  BOOST_TEST_REQUIRE(wait_for_decisions(checkpoint, killed_at), "the resumed search made none");
  kill(pid, SIGTERM);
  BOOST_TEST_REQUIRE(wait_for(pid) != 0, "the search ended before the signal; slow it down");
  BOOST_TEST(!fs::exists(resumed));
  const std::size_t stopped_at = decisions_in(checkpoint);
  BOOST_TEST(stopped_at > killed_at);
  BOOST_TEST(stopped_at < minimizations);
  {
    // After the two ends and at least one bisection the checkpoint keeps one bracket of at
    // most half the configurations (their positions only: every packing stays listed).
    const auto f = jam::h5::File::open_read(checkpoint.string());
    const auto kept = f.read_dataset_u32("saved_kept");
    const std::size_t count = std::count(kept.begin(), kept.end(), 1u);
    BOOST_TEST(f.read_dataset("saved_packing_fraction").size() == kept.size());
    BOOST_TEST(count >= 2u);
    BOOST_TEST(count <= kept.size() / 2 + 1);
    BOOST_TEST(f.read_dataset("saved_s").size() == count * 2 * 1024);
  }

  BOOST_TEST_REQUIRE(wait_for(spawn_jam(interrupted)) == 0);
  BOOST_TEST(!fs::exists(checkpoint));
  BOOST_TEST((slurp(ref) == slurp(resumed)), "resumed search differs from the uninterrupted one");
  fs::remove_all(kDir);
}
