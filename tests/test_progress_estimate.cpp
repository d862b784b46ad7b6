// What a campaign reports of its cost and its time left: the ETA from the planner's estimate
// calibrated by the finished runs (campaign/progress_estimate.hpp), and each run's recorded
// core-seconds, its thread's CPU time, which --until-decided --budget counts
// (campaign/campaign_dir.hpp).
#define BOOST_TEST_MODULE progress_estimate
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "campaign/campaign_dir.hpp"
#include "campaign/progress_estimate.hpp"

namespace fs = std::filesystem;
using jam::ProgressEstimate;

// The planner estimates 10x the steps the runs take (as at slow rates near jamming). Ten runs
// of equal cost at 1e6 real particle-steps each, done at 1e6 particle-steps per second: after
// four are finished (4 s), six remain, 6 s.
BOOST_AUTO_TEST_CASE(eta_is_calibrated_by_the_finished_runs) {
  ProgressEstimate p(10 * 1e7);
  for (int k = 0; k < 4; ++k) p.finished(1e7, 1e6);
  BOOST_TEST(std::abs(p.seconds_left(4e6, 4.0) - 6.0) < 1e-9);
  // Uncalibrated, the estimate alone would have said (1e8 - 4e6) / 1e6 = 96 s.
  ProgressEstimate blind(10 * 1e7);
  BOOST_TEST(blind.seconds_left(4e6, 4.0) > 90.0);
}

// Half of a fifth run is done too (live steps 4.5e6 at 4.5 s): 5.5 s are left, not 6.
BOOST_AUTO_TEST_CASE(eta_counts_the_part_of_runs_under_way) {
  ProgressEstimate p(10 * 1e7);
  for (int k = 0; k < 4; ++k) p.finished(1e7, 1e6);
  BOOST_TEST(std::abs(p.seconds_left(4.5e6, 4.5) - 5.5) < 1e-9);
  // Nothing measured yet: no ETA rather than a division by zero.
  BOOST_TEST(ProgressEstimate(1e7).seconds_left(0.0, 0.0) == 0.0);
}

namespace {

jam::PlannedRun run_at(const fs::path& out) {
  jam::PlannedRun run;
  run.config.out = out.string();
  return run;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace

// A record with cpu_seconds counts those; an older one, without, counts its wall seconds; a
// missing record counts nothing.
BOOST_AUTO_TEST_CASE(recorded_core_seconds_prefer_cpu_and_read_older_records) {
  const fs::path dir = fs::temp_directory_path() / ("jam-progress-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write(dir / "a.record", "status = 'done'\nwall_seconds = 30.0\ncpu_seconds = 12.5\n");
  write(dir / "b.record", "status = 'done'\nwall_seconds = 30.0\n");
  BOOST_TEST(*jam::recorded_core_seconds(run_at(dir / "a.h5")) == 12.5);
  BOOST_TEST(*jam::recorded_core_seconds(run_at(dir / "b.h5")) == 30.0);
  BOOST_TEST(!jam::recorded_core_seconds(run_at(dir / "c.h5")).has_value());
  fs::remove_all(dir);
}

// The thread clock counts this thread's work and not its sleep nor another thread's work:
// what makes a run's cost independent of what else the machine runs.
BOOST_AUTO_TEST_CASE(thread_cpu_seconds_count_this_thread_only) {
  const double start = jam::thread_cpu_seconds();
  std::thread busy([] {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
    volatile double x = 0;
    while (std::chrono::steady_clock::now() < until) x = x + 1;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  busy.join();
  BOOST_TEST(jam::thread_cpu_seconds() - start < 0.1);
  double spent = 0;
  std::thread([&] {
    const double t0 = jam::thread_cpu_seconds();
    volatile double x = 0;
    while (jam::thread_cpu_seconds() - t0 < 0.2) x = x + 1;
    spent = jam::thread_cpu_seconds() - t0;
  }).join();
  BOOST_TEST(spent >= 0.2);
}
