#include "campaign/campaign_runner.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "campaign/campaign_dir.hpp"
#include "campaign/campaign_lock.hpp"
#include "campaign/manifest.hpp"
#include "campaign/progress_estimate.hpp"
#include "campaign/progress_text.hpp"
#include "campaign/restore_starts.hpp"
#include "campaign/run_chains.hpp"
#include "campaign/run_plan.hpp"
#include "campaign/run_queue.hpp"
#include "campaign/throughput.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/terminal_text.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam {
namespace {

/// Refuses the whole campaign before any work when one of its runs is beyond the limits.
void validate_costs(const Campaign& c, const std::vector<PlannedRun>& plan, bool force) {
  for (const auto& run : plan) {
    try {
      validate_cost(run.config, run.n, force);
    } catch (const ConfigError& e) {
      throw CampaignError(fmt::format("{}: run {}: {}", c.source_path, run.name, e.what()));
    }
  }
}

/// A run file that is not the planned run's result (damaged, or written with other
/// parameters) is moved aside to <name>.h5.rejected (.rejected.1, .2, ... when that name is
/// taken), never deleted nor overwritten: it may be someone's result.
void set_aside(const PlannedRun& run) {
  move_aside(run.config.out, ".rejected");
}

}  // namespace

int campaign_status_code(const std::map<RunStatus, std::size_t>& totals) {
  auto count = [&totals](RunStatus s) {
    const auto it = totals.find(s);
    return it == totals.end() ? std::size_t{0} : it->second;
  };
  if (count(RunStatus::kFailed) + count(RunStatus::kCorrupt) > 0) return kStatusProblems;
  if (count(RunStatus::kMissing) + count(RunStatus::kPartial) > 0) return kStatusUnfinished;
  return 0;
}

int run_campaign(const Campaign& c, const CampaignRunOptions& options, const Ranks& ranks) {
  const std::vector<PlannedRun> plan = plan_runs(c);
  validate_costs(c, plan, options.force);
  std::optional<CampaignLock> owner;
  if (ranks.rank == 0) {
    try {
      check_output_directory("output", c.output);
    } catch (const ConfigError& e) {
      throw CampaignError(fmt::format("{}: {}", c.source_path, e.what()));
    }
    std::error_code ec;
    std::filesystem::create_directories(c.output, ec);
    if (ec) {
      throw CampaignError(
          fmt::format("{}: output: cannot create '{}': {}", c.source_path, c.output, ec.message()));
    }
    const bool sharded = options.shards > 1;
    owner.emplace(c.output, sharded ? fmt::format("{}-of-{}", options.shard, options.shards) : "");
    // Other shares may be writing: only a runner that owns the whole directory cleans up.
    if (!sharded) remove_stale_temporaries(c.output);
    prepare_campaign_directory(c);
    // The plan first, so that a campaign stopped by any means leaves a manifest of what it
    // runs (the stages after it read the runs through it).
    write_manifest(c, plan);
    // Runs redone from another campaign's starts: those gone rewritten there first.
    restore_starts(c, options.quiet);
  }
  barrier();

  // Rank 0 decides what is pending and everybody works from that one list, so no run is done
  // twice even while other ranks already start writing checkpoints.
  std::vector<std::int64_t> pending, task_codes;
  std::vector<std::string> task_notes;
  std::size_t already_done = 0;
  double earlier_estimated = 0.0, earlier_steps = 0.0;  // of the done runs, for the ETA
  if (ranks.rank == 0) {
    std::vector<std::size_t> scope(plan.size());
    for (std::size_t k = 0; k < plan.size(); ++k) scope[k] = k;
    if (options.shards > 1) scope = shard_of(plan, options.shard, options.shards);
    for (const std::size_t k : scope) {
      const RunStatus s = run_status(plan[k]);
      if (s == RunStatus::kDone) {
        ++already_done;
        if (const auto r = read_run_record(plan[k]); r && r->particle_steps > 0) {
          earlier_estimated += plan[k].estimated_particle_steps;
          earlier_steps += static_cast<double>(r->particle_steps);
        }
      } else if (s != RunStatus::kFailed || options.retry_failed) {
        if (s == RunStatus::kCorrupt) set_aside(plan[k]);
        pending.push_back(static_cast<std::int64_t>(k));
      }
    }
    RunTasks t = plan_tasks(plan, pending, options.retry_failed);
    task_codes = tasks_for_broadcast(t);
    task_notes = std::move(t.notes);
  }
  // Every rank learns the same tasks (a chained run with the run it continues from).
  const RunTasks planned =
      tasks_from_broadcast(broadcast_from_root(std::move(task_codes)), plan.size());
  const std::vector<std::vector<std::size_t>>& tasks = planned.tasks;
  std::size_t to_run = 0, starts_only = 0;
  std::vector<double> task_costs;
  for (const auto& t : tasks) {
    for (const auto k : t) (planned.start_only[k] ? starts_only : to_run) += 1;
    task_costs.push_back(task_cost(plan, planned, t));
  }

  const std::atomic<bool>& stop_requested = install_stop_handlers();
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  const int jobs = options.jobs > 0 ? options.jobs : static_cast<int>(hardware);
  const bool show = !options.quiet && ranks.rank == 0;
  const bool tty = show && isatty(STDERR_FILENO);
  if (show) {
    for (const auto& note : task_notes) fmt::print("campaign {}: {}\n", c.name, note);
    fmt::print("campaign {}: {} runs, {} done, {} to run", c.name, plan.size(), already_done,
               to_run);
    if (starts_only > 0) fmt::print(", {} done runs again to their lost starts", starts_only);
    if (ranks.size > 1) fmt::print(" on {} ranks", ranks.size);
    if (options.shards > 1) fmt::print(" in share {} of {}", options.shard, options.shards);
    fmt::print(" ({} threads per process)\n", jobs);
    std::fflush(stdout);
  }

  std::vector<std::int64_t> task_indices(tasks.size());
  for (std::size_t k = 0; k < tasks.size(); ++k) task_indices[k] = static_cast<std::int64_t>(k);
  const int workers = std::min<int>(jobs, static_cast<int>(tasks.size()));
  RunQueue queue(task_indices, task_costs, ranks, workers, &stop_requested);
  ProgressEstimate progress(queue.local_estimate());
  progress.calibrate(earlier_estimated, earlier_steps);
  // unwritten: runs that could not write their output (a full disk): not failed, since nothing
  // records them so and `campaign status` shows them missing; the next run redoes them.
  std::atomic<std::size_t> finished{0}, failed{0}, interrupted{0}, unwritten{0};
  std::atomic<int> active{0};
  std::atomic<std::size_t> taken{0};  // runs this process took from the queue
  std::atomic<bool> cannot_write{false};
  std::atomic<std::uint64_t> particle_steps{0};
  std::mutex print_mutex;
  enum class Outcome { kDone, kFailed, kInterrupted, kCannotWrite };
  auto control_of = [&](const PlannedRun& run) {
    RunControl control;
    control.checkpoint_interval_seconds = run.config.checkpoint_interval;
    control.stop = &stop_requested;
    control.particle_steps = &particle_steps;
    return control;
  };
  // One compression taken from the queue; nullopt when it stopped on request (its checkpoint
  // kept). planned_steps: what the plan charged it, for the ETA.
  auto compress = [&](const PlannedRun& run, const RunControl& control,
                      double planned_steps) -> std::optional<RunSummary> {
    ++taken;
    const RunSummary s = run_compression(run.config, control);
    if (s.interrupted) {
      ++interrupted;
      return std::nullopt;
    }
    progress.finished(planned_steps, static_cast<double>(s.counted_particle_steps), !s.resumed);
    return s;
  };
  // A done run again, only as far as the start its child lost (run_chains.hpp). Not a run: no
  // record is written whatever happens, so the run's own (and its cost) stays.
  auto start_again = [&](const PlannedRun& run) {
    RunControl control = control_of(run);
    control.start_only = true;
    const double cpu_start = thread_cpu_seconds();
    try {
      const std::optional<RunSummary> s = compress(run, control, run.start_particle_steps);
      if (!s) return Outcome::kInterrupted;
      std::lock_guard lock(print_mutex);
      fmt::print("{}campaign {}: {} left its start at {:.6g} again ({:.0f} CPU seconds)\n",
                 tty ? "\n" : "", c.name, run.name, s->final_packing_fraction,
                 thread_cpu_seconds() - cpu_start);
      std::fflush(stdout);
      return Outcome::kDone;
    } catch (const std::exception& e) {
      const bool write = dynamic_cast<const WriteError*>(&e) != nullptr;
      (write ? unwritten : failed) += 1;
      if (write) cannot_write = true;
      std::lock_guard lock(print_mutex);
      fmt::print(stderr, "{}jam: {} could not leave its start again: {}\n", tty ? "\n" : "",
                 run.name, e.what());
      return write ? Outcome::kCannotWrite : Outcome::kFailed;
    }
  };
  auto run_one = [&](const PlannedRun& run) {
    RunRecord record;
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_seconds();
    double earlier_cpu = 0.0;  // of the attempts before a checkpoint it resumed from
    try {
      const std::optional<RunSummary> s =
          compress(run, control_of(run), run.estimated_particle_steps);
      if (!s) return Outcome::kInterrupted;
      record.status = "done";
      record.steps = static_cast<std::int64_t>(s->steps);
      if (!s->resumed) record.particle_steps = static_cast<std::int64_t>(s->counted_particle_steps);
      earlier_cpu = s->earlier_cpu_seconds;
    } catch (const WriteError& e) {
      // Not the run's fault: no record, so the run stays to be done (or resumed from its
      // checkpoint) by the next `campaign run`; but no further runs in this directory.
      std::lock_guard lock(print_mutex);
      fmt::print(stderr,
                 "{}jam: error: run {} could not write its output: {}; no further runs "
                 "started\n",
                 tty ? "\n" : "", run.name, e.what());
      cannot_write = true;
      ++unwritten;
      return Outcome::kCannotWrite;
    } catch (const std::exception& e) {
      record.status = "failed";
      record.error = e.what();
      ++failed;
      std::lock_guard lock(print_mutex);
      fmt::print(stderr, "{}jam: run {} failed: {}\n", tty ? "\n" : "", run.name,
                 visible(e.what()));
    }
    record.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    record.cpu_seconds = thread_cpu_seconds() - cpu_start + earlier_cpu;
    try {
      write_run_record(run, record);
    } catch (const std::exception& e) {
      // The directory cannot take even a small record (full disk, gone unwritable): every
      // further run would fail the same way after doing all its work, so take no more.
      std::lock_guard lock(print_mutex);
      fmt::print(stderr, "{}jam: error: {}; no further runs started\n", tty ? "\n" : "", e.what());
      if (record.status == "failed") {  // not recorded: status shows it missing
        --failed;
        ++unwritten;
      }
      cannot_write = true;
    }
    ++finished;
    return record.status == "done" ? Outcome::kDone : Outcome::kFailed;
  };
  auto worker = [&](int id) {
    struct Active {
      std::atomic<int>& count;
      ~Active() { --count; }
    } active_guard{active};
    while (true) {
      if (stop_requested.load() || cannot_write.load()) {
        queue.quit(id);  // rank 0 stops waiting for this worker
        return;
      }
      const std::optional<std::size_t> index = queue.next(id);
      if (!index) return;
      const std::vector<std::size_t>& task = tasks[*index];
      // A chained run starts only after the run it continues from is done.
      for (std::size_t m = 0; m < task.size(); ++m) {
        if (m > 0 && (stop_requested.load() || cannot_write.load())) break;
        const Outcome outcome =
            planned.start_only[task[m]] ? start_again(plan[task[m]]) : run_one(plan[task[m]]);
        if (outcome == Outcome::kCannotWrite) {
          queue.quit(id);
          return;
        }
        if (outcome == Outcome::kFailed && m + 1 < task.size()) {
          std::lock_guard lock(print_mutex);
          fmt::print(stderr, "{}jam: not started, since {} failed: {}\n", tty ? "\n" : "",
                     plan[task[m]].name, plan[task[m + 1]].name);
        }
        if (outcome != Outcome::kDone) break;
      }
    }
  };

  const auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> threads;
  for (int k = 0; k < workers; ++k) {
    ++active;
    threads.emplace_back(worker, k);
  }
  // Progress: on a terminal a line redrawn every half second; without one (a batch log) a
  // dated line every options.log_seconds, so a day-long Slurm log shows how far it got.
  double core_seconds = 0.0, last_line = 0.0;
  while (show && active.load() > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(tty ? 500 : 100));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    core_seconds += (tty ? 0.5 : 0.1) * active.load();
    if (!tty && elapsed - last_line < options.log_seconds) continue;
    last_line = elapsed;
    const double done_steps = static_cast<double>(particle_steps.load());
    const double speed = elapsed > 0 ? done_steps / elapsed : 0.0;
    const double eta = progress.seconds_left(done_steps, elapsed);
    const std::string line =
        fmt::format("runs {}/{} done, {:.3g} core-hours, {:.3g} particle-steps/s, ETA {}",
                    already_done + finished.load(), plan.size(), core_seconds / 3600.0, speed,
                    duration_text(eta));
    std::lock_guard lock(print_mutex);
    if (tty) {
      fmt::print(stderr, "\r  {}      ", line);
    } else {
      fmt::print(stderr, "jam: {} campaign {}: {}\n", utc_time(), c.name, line);
    }
    std::fflush(stderr);
  }
  for (auto& t : threads) t.join();
  if (tty) fmt::print(stderr, "\r{:80}\r", "");

  if (ranks.size > 1 && !options.quiet) {
    fmt::print("rank {}: took {} runs ({})\n", ranks.rank, taken.load(),
               queue.dynamic() ? "handed out as workers became free" : "split in advance");
    std::fflush(stdout);
  }
  // 2 as for any error that kept jam from doing what was asked (a full disk), 1 for failed runs.
  int status = interrupted.load() > 0 || stop_requested.load()
                   ? 130
                   : (unwritten.load() > 0 ? 2 : (failed.load() > 0 ? 1 : 0));
  status = max_over_ranks(status);
  barrier();
  if (ranks.rank == 0) write_manifest(c, plan);
  if (show) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(
        "campaign {}: {} runs finished by this process in {}, {} failed{}{}; manifest "
        "{}/manifest.toml\n",
        c.name, finished.load(), duration_text(wall), failed.load(),
        unwritten.load() > 0
            ? fmt::format(", {} could not write their output (run again to redo them)",
                          unwritten.load())
            : std::string(),
        status == 130 ? ", interrupted (run again to resume)" : "", c.output);
  }
  return status;
}

int print_campaign_status(const std::string& directory, bool json) {
  // The runs are looked for in DIR itself, wherever the campaign was run from and whatever its
  // file's `output` says (a relative output is relative to where it was run).
  Campaign c = stored_campaign(directory);
  c.output = directory;
  const std::vector<PlannedRun> plan = plan_runs(c);
  std::map<RunStatus, std::size_t> totals;
  std::map<std::pair<std::int64_t, double>, std::map<double, std::map<RunStatus, int>>> table;
  std::vector<std::string> problems;
  std::size_t unverified = 0;  // done, but of schema 1: its attributes carry no checksum
  nlohmann::json runs = nlohmann::json::object();
  for (const auto& run : plan) {
    std::string detail;
    const RunStatus s = run_status(run, &detail);
    ++totals[s];
    if (s == RunStatus::kDone && !detail.empty()) ++unverified;
    ++table[{run.n, run.phi_init}][run.log10_rate][s];
    if (s == RunStatus::kFailed || s == RunStatus::kCorrupt) {
      problems.push_back(fmt::format("  {} {}: {}", to_string(s), run.name, detail));
    }
    runs[run.name] = {{"status", to_string(s)}, {"detail", detail}};
  }
  const int status = campaign_status_code(totals);
  if (json) {
    nlohmann::json out = {{"campaign", c.name},
                          {"directory", directory},
                          {"runs", plan.size()},
                          {"exit_status", status}};
    for (RunStatus s : {RunStatus::kDone, RunStatus::kPartial, RunStatus::kMissing,
                        RunStatus::kFailed, RunStatus::kCorrupt}) {
      out["totals"][to_string(s)] = totals[s];
    }
    out["run"] = std::move(runs);
    fmt::print("{}\n", out.dump(2));
    return status;
  }
  fmt::print("campaign {} in {}: {} runs\n", c.name, directory, plan.size());
  for (RunStatus s : {RunStatus::kDone, RunStatus::kPartial, RunStatus::kMissing,
                      RunStatus::kFailed, RunStatus::kCorrupt}) {
    fmt::print("  {:8} {}\n", to_string(s), totals[s]);
  }
  if (unverified > 0)
    fmt::print(
        "  unverified: {} of the done runs (written before run files checksummed their "
        "attributes; --json names them)\n",
        unverified);
  fmt::print("\n{:>8} {:>9}", "N", "phi_init");
  for (double lr : c.log10_rates) fmt::print(" {:>10}", fmt::format("rate 1e{:g}", lr));
  fmt::print("   (done/samples)\n");
  for (const auto& [key, by_rate] : table) {
    fmt::print("{:>8} {:>9.4f}", key.first, key.second);
    for (double lr : c.log10_rates) {
      auto it = by_rate.find(lr);
      const int done =
          it == by_rate.end()
              ? 0
              : (it->second.count(RunStatus::kDone) ? it->second.at(RunStatus::kDone) : 0);
      fmt::print(" {:>10}", fmt::format("{}/{}", done, c.samples));
    }
    fmt::print("\n");
  }
  for (const std::string& problem : problems) fmt::print("\n{}", visible(problem));
  if (!problems.empty()) fmt::print("\n");
  return status;
}

/// The plan's error so far: the finished runs' recorded CPU seconds (thread clock) against what
/// the plan gives them at this throughput, in all and per rate.
void print_measured_against_plan(const std::vector<PlannedRun>& plan, const Throughput& speed) {
  std::map<double, std::pair<double, double>> by_rate;  // log10 rate -> (measured, planned)
  double measured = 0.0, planned = 0.0;
  std::size_t finished = 0;
  for (const auto& run : plan) {
    const auto seconds = recorded_core_seconds(run);
    if (!seconds) continue;
    ++finished;
    const double p = speed.core_seconds(run.n, run.estimated_particle_steps);
    measured += *seconds;
    planned += p;
    by_rate[run.log10_rate].first += *seconds;
    by_rate[run.log10_rate].second += p;
  }
  if (finished == 0) return;
  std::string rates;
  for (const auto& [rate, mp] : by_rate)
    rates += fmt::format("{}1e{:g} {:.2f}", rates.empty() ? "" : ", ", rate, mp.first / mp.second);
  fmt::print(
      "  measured so far: {} finished runs took {:.3g} core-hours, planned {:.3g} for them "
      "(measured / planned {:.2f}; by rate {})\n",
      finished, measured / 3600.0, planned / 3600.0, measured / planned, rates);
}

int print_campaign_plan(const Campaign& c, Throughput* measured_speed, bool probe) {
  const std::vector<PlannedRun> plan = plan_runs(c);
  double total = 0.0, seconds = 0.0;
  std::map<std::int64_t, double> by_size;
  // Stored measurements (or the probe, asked or for want of them), then the campaign's own
  // finished runs where it has them: the same plan every time for the same runs.
  const Throughput base = plan_throughput(c.run, c.sizes, probe);
  const Throughput speed = with_finished_runs(base, plan);
  for (const auto& run : plan) {
    total += run.estimated_particle_steps;
    by_size[run.n] += run.estimated_particle_steps;
    seconds += speed.core_seconds(run.n, run.estimated_particle_steps);
  }
  if (measured_speed) *measured_speed = speed;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  fmt::print("campaign {}: {}D, {} runs ({} sizes x {} phi_init x {} rates x {} samples)\n", c.name,
             c.run.dim, plan.size(), c.sizes.size(), c.phi_init.size(), c.log10_rates.size(),
             c.samples);
  fmt::print("  particle-steps (force evaluations x particles, relaxation included): {:.3g}\n",
             total);
  for (const auto& [n, steps] : by_size) {
    fmt::print("    N = {:>7}: {:.3g} ({:.1f}%), probe {:.3g} particle-steps/s per core ({})\n", n,
               steps, 100.0 * steps / total, speed.at(n), speed.source.at(n));
  }
  fmt::print(
      "  price: the probe's throughput ({}D, overdamped Euler near jamming at each N), from the "
      "campaign's finished runs, else stored measurements, else this machine's probe (`--probe`); "
      "one force evaluation of the integrator costs {:.2g} of its steps\n",
      c.run.dim, speed.evaluation_cost);
  fmt::print("  estimated cost: {:.3g} core-hours; {} on {} cores of this machine\n",
             seconds / 3600.0, duration_text(seconds / cores), cores);
  fmt::print("  longest run: {} ({:.3g} core-hours)\n", plan.front().name,
             speed.core_seconds(plan.front().n, plan.front().estimated_particle_steps) / 3600.0);
  if (!c.chain_phi_init.empty()) {
    Campaign unchained = c;
    unchained.chain_phi_init.clear();
    double unchained_seconds = 0.0;
    for (const auto& run : plan_runs(unchained))
      unchained_seconds += speed.core_seconds(run.n, run.estimated_particle_steps);
    fmt::print(
        "  chained starts (chain_phi_init) save {:.0f}%: {:.3g} core-hours instead of {:.3g} "
        "with every rate compressed from phi_init\n",
        100.0 * (1.0 - seconds / unchained_seconds), seconds / 3600.0, unchained_seconds / 3600.0);
  }
  // The plan's error: the runs against the price they were not measured by.
  print_measured_against_plan(plan, base);
  return 0;
}

}  // namespace jam
