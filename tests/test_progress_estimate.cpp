// What a campaign reports of its cost and its time left: the ETA from the planner's estimate
// calibrated by the finished runs (campaign/progress_estimate.hpp), and each run's recorded
// core-seconds, its thread's CPU time, which --until-decided --budget counts
// (campaign/campaign_dir.hpp).
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "campaign/campaign_dir.hpp"
#include "campaign/progress_estimate.hpp"
#include "campaign/progress_text.hpp"
#include "sim/run/compression_run.hpp"

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

// A resumed campaign: earlier processes finished runs whose records hold 4e6 particle-steps
// against 4e7 planned. Before this process finishes any run, its ETA uses their ratio: 1e6
// live steps in 1 s, 1e8 planned ahead, so 0.1 * 1e8 - 1e6 = 9e6 steps, 9 s; the planner's
// scale alone would say 99 s.
BOOST_AUTO_TEST_CASE(a_resumed_campaign_is_calibrated_by_its_earlier_runs) {
  ProgressEstimate p(1e8);
  p.calibrate(4e7, 4e6);
  BOOST_TEST(std::abs(p.seconds_left(1e6, 1.0) - 9.0) < 1e-9);
  BOOST_TEST(std::abs(ProgressEstimate(1e8).seconds_left(1e6, 1.0) - 99.0) < 1e-9);
  // Runs finished in this process join the ratio: 1e7 planned took 3e6, so (4e6 + 3e6) /
  // (4e7 + 1e7) = 0.14 of the 9e7 planned ahead, less the 1e6 of runs under way: 11.6 s at
  // 1e6 per second (live steps 4e6 in 4 s).
  p.finished(1e7, 3e6);
  BOOST_TEST(std::abs(p.seconds_left(4e6, 4.0) - 11.6) < 1e-9);
}

// A run resumed from a checkpoint did only the rest of its estimate: it leaves the remaining
// work, but its few steps against its whole estimate must not drag the ratio down.
BOOST_AUTO_TEST_CASE(a_resumed_run_does_not_calibrate) {
  ProgressEstimate p(10 * 1e7);
  for (int k = 0; k < 4; ++k) p.finished(1e7, 1e6);
  p.finished(1e7, 1e5, false);  // resumed near its end
  // Ratio 0.1 still: five of ten runs left, 5e6 steps at 1e6 per second (live 4.1e6 in 4.1 s).
  BOOST_TEST(std::abs(p.seconds_left(4.1e6, 4.1) - 5.0) < 1e-9);
}

// The progress counts force evaluations x N, the planner's unit (campaign/run_plan.cpp), each
// one once: the relaxation's and the compression's (a run without a search counts exactly its
// evaluations) and the jamming search's minimizations (on a scratch copy, so beyond them).
BOOST_AUTO_TEST_CASE(runs_count_their_force_evaluations) {
  const fs::path dir = fs::temp_directory_path() / ("jam-count-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  jam::SimConfig c;
  c.n = 128;
  c.phi_init = 0.80;
  c.phi_stop = 0.86;
  c.phi_step = 0.002;
  c.compression_rate = 1e-3;
  c.seed = 5;
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.out = (dir / "plain.h5").string();
  std::atomic<std::uint64_t> live{0};
  jam::RunControl control;
  control.particle_steps = &live;
  const jam::RunSummary plain = jam::run_compression(c, control);
  BOOST_TEST(plain.force_evaluations > plain.steps);  // Chebyshev: several per step
  BOOST_TEST(plain.counted_particle_steps == plain.force_evaluations * 128);
  BOOST_TEST(live.load() == plain.counted_particle_steps);

  c.jamming_point = true;
  c.out = (dir / "search.h5").string();
  live = 0;
  const jam::RunSummary searched = jam::run_compression(c, control);
  BOOST_TEST(searched.counted_particle_steps > searched.force_evaluations * 128 + 1000 * 128);
  BOOST_TEST(live.load() == searched.counted_particle_steps);
  fs::remove_all(dir);
}

BOOST_AUTO_TEST_CASE(durations_read_as_a_person_reads_them) {
  BOOST_TEST(jam::duration_text(42.0) == "42 s");
  BOOST_TEST(jam::duration_text(600.0) == "10.0 min");
  BOOST_TEST(jam::duration_text(9 * 3600.0) == "9.0 h");
  BOOST_TEST(jam::duration_text(3 * 86400.0) == "3.0 days");
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
  // The whole record, for the ETA's calibration: its particle-steps (0 where an old record
  // has none).
  write(dir / "d.record",
        "status = 'done'\nwall_seconds = 3.0\ncpu_seconds = 2.5\nsteps = 36809\n"
        "particle_steps = 9000000\n");
  const auto d = jam::read_run_record(run_at(dir / "d.h5"));
  BOOST_TEST((d && d->status == "done" && d->steps == 36809 && d->cpu_seconds == 2.5 &&
              d->particle_steps == 9000000));
  BOOST_TEST(jam::read_run_record(run_at(dir / "b.h5"))->particle_steps == 0);
  // What write_run_record writes, read_run_record reads back.
  jam::RunRecord e;
  e.status = "done";
  e.steps = 12;
  e.particle_steps = 3456;
  jam::write_run_record(run_at(dir / "e.h5"), e);
  const auto back = jam::read_run_record(run_at(dir / "e.h5"));
  BOOST_TEST((back && back->steps == 12 && back->particle_steps == 3456));
  BOOST_TEST(!jam::read_run_record(run_at(dir / "c.h5")).has_value());
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
