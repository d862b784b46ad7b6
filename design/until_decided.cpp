#include "design/until_decided.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_dir.hpp"
#include "campaign/run_plan.hpp"
#include "checks/verdict_file.hpp"
#include "design/sequence_cost.hpp"
#include "design/until_decided_look.hpp"
#include "design/until_decided_options.hpp"
#include "design/until_decided_state.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam::design {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// The exit status of the stored checks.json (a sequence finished by an earlier invocation).
int stored_exit_status(const Campaign& c) {
  return checks::exit_status(
      checks::read_verdict_file((fs::path(c.output) / "checks.json").string()).verdicts);
}

/// Sleeps `seconds` in short steps; false when a stop was asked for meanwhile.
bool sleep_unless_stopped(double seconds) {
  const auto& stop = install_stop_handlers();
  for (int k = 0; k < static_cast<int>(seconds * 10); ++k) {
    if (stop.load()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return !stop.load();
}

/// --shard: waits until every run of this look's plan (`added`: the state's, read when the
/// look began) is done, other shards' too. Never the plan in added-samples.toml: shard 1 may
/// already have judged this look and written the next one there, whose runs no shard is
/// running yet. 0, or 1 when a run failed, 130 when stopped. A run seen done is not looked at
/// again (each look verifies the file's checksums).
int wait_for_runs(const Campaign& c, const UntilDecidedOptions& o, const SampleCounts& added) {
  auto last = std::chrono::steady_clock::now();
  std::set<std::string> done;
  const std::vector<PlannedRun> plan = plan_runs(c, added);
  for (;;) {
    std::size_t pending = 0;
    for (const auto& run : plan) {
      if (done.count(run.name)) continue;
      const RunStatus s = run_status(run);
      if (s == RunStatus::kFailed || s == RunStatus::kCorrupt) return 1;
      if (s == RunStatus::kDone)
        done.insert(run.name);
      else
        ++pending;
    }
    if (pending == 0) return 0;
    if (std::chrono::steady_clock::now() - last > std::chrono::minutes(5)) {
      fmt::print("until-decided: waiting for {} runs of other shards\n", pending);
      std::fflush(stdout);
      last = std::chrono::steady_clock::now();
    }
    if (!sleep_unless_stopped(o.poll_seconds)) return 130;
  }
}

/// --shard, shards other than 1: waits until added-samples.toml holds `next` (the state's
/// plan for this look); false when stopped.
bool wait_for_plan(const Campaign& c, const UntilDecidedOptions& o, const SampleCounts& state) {
  SampleCounts next;  // in the campaign's own spelling, as the file is read
  for (const auto& [id, count] : state) next[campaign_ensemble(c, id).value_or(id)] = count;
  for (;;) {
    try {
      if (read_added_samples(c) == next) return true;
    } catch (const CampaignError&) {
      // Being replaced (atomically, but a reader may see none): look again.
    }
    if (!sleep_unless_stopped(o.poll_seconds)) return false;
  }
}

/// Refuses to go on with a sequence begun with other options (until_decided_options.hpp): its
/// looks and verdicts hold only for those. A state written before options were recorded takes
/// this invocation's, and says so.
void require_same_options(const Campaign& c, const UntilDecidedOptions& o, State& s) {
  const json now = sequence_record(c, sequence_question(c, o), o.alpha);
  if (s.options.is_null()) {
    if (!s.looks.empty())
      fmt::print(
          "until-decided: {} records no options (begun by an earlier jam): taking "
          "these\n",
          state_path(c));
    s.options = now;
    return;
  }
  if (const std::string why = sequence_difference(s.options, now); !why.empty())
    throw std::runtime_error(fmt::format(
        "until-decided: {}: {}; give the recorded value to go on with it, or move it away to "
        "begin a new sequence",
        state_path(c), why));
}

/// The exit status of the verdicts decided so far, the others undecided: 1 when one failed,
/// else 3.
int decided_so_far(const State& s) {
  for (const auto& [key, v] : s.decided.items())
    if (v.value("status", "") == "fail") return 1;
  return 3;
}

/// "" when the runs of the state's next batch fit what is left of the budget (or cannot be
/// costed yet: nothing measured); otherwise why not. Checked before every batch, a resumed one
/// too: a smaller --budget given to go on stops the sequence before its runs.
std::string over_budget(const Campaign& c, const UntilDecidedOptions& o, const State& s) {
  const Cost cost = measured_cost(plan_runs(c, s.next));
  const double seconds = batch_seconds(c, s.next, cost);
  if (!(std::isfinite(seconds) && seconds > 0)) return "";
  const double budget = o.budget_core_hours * 3600.0;
  if (cost.spent_seconds + seconds <= budget) return "";
  return fmt::format(
      "the next batch (about {:.3g} core-hours) would exceed the --budget of {:g} core-hours "
      "({:.3g} spent): not run; a larger --budget goes on with it",
      seconds / 3600, o.budget_core_hours, cost.spent_seconds / 3600);
}

}  // namespace

void validate_until_decided(const UntilDecidedOptions& o) {
  if (!(std::isfinite(o.budget_core_hours) && o.budget_core_hours > 0)) {
    throw std::invalid_argument(
        fmt::format("{}: core-hours must be a finite number > 0", o.budget_core_hours));
  }
}

CampaignQuestion sequence_question(const Campaign& c, const UntilDecidedOptions& o) {
  CampaignQuestion question = c.question;
  if (!o.phi_min && !o.phi_max) return question;
  if (!question.states_range() && !(o.phi_min && o.phi_max))
    throw std::invalid_argument(fmt::format(
        "{} {:g}: the campaign file states no range ([question] phi_min, phi_max) to take the "
        "other end from; give both --phi-min and --phi-max",
        o.phi_min ? "--phi-min" : "--phi-max", o.phi_min ? *o.phi_min : *o.phi_max));
  for (const auto& [flag, value] : {std::pair{"--phi-min", o.phi_min}, {"--phi-max", o.phi_max}})
    if (value && !(*value > 0 && *value < 1))
      throw std::invalid_argument(
          fmt::format("{} {:g}: must be a packing in (0, 1)", flag, *value));
  question.phi_min = o.phi_min ? o.phi_min : question.phi_min;
  question.phi_max = o.phi_max ? o.phi_max : question.phi_max;
  if (!(*question.phi_min < *question.phi_max))
    throw std::invalid_argument(fmt::format("--phi-max {:g}: must exceed phi_min {:g}",
                                            *question.phi_max, *question.phi_min));
  return question;
}

namespace {

/// The looks, from the state on: runs, judges, adds samples, until decided or out of budget.
int run_looks(const Campaign& c, const CampaignRunOptions& run, const UntilDecidedOptions& o,
              const Ranks& ranks) {
  const bool decider = ranks.rank == 0 && run.shard == 1;
  std::vector<checks::Verdict> verdicts;
  for (bool first = true;; first = false) {
    State s = read_state(c);
    if (first) require_same_options(c, o, s);
    if (s.finished) break;
    if (const std::string why = over_budget(c, o, s); !why.empty()) {
      fmt::print("until-decided: {}\n", why);
      return decided_so_far(s);
    }
    // Restores added-samples.toml from the state (a new directory has neither yet).
    if (decider && fs::is_directory(c.output)) write_state(c, s);
    barrier();
    // The other shards run this look's plan, which shard 1 writes to added-samples.toml after
    // the state: wait until the file says what the state says.
    if (!decider && run.shards > 1 && !wait_for_plan(c, o, s.next)) return 130;
    const int looks_before = static_cast<int>(s.looks.size());
    int status = run_campaign(c, run, ranks);
    if (status == 0 && run.shards > 1) status = wait_for_runs(c, o, s.next);
    if (status != 0) return status;
    std::int64_t more = 0;
    if (decider) {
      more = judge_look(c, o, s, &verdicts) ? 1 : 0;
      // The verdicts before the state that says they are final: a stop or a kill between the
      // two leaves the look to be judged again, never a finished state without checks.json.
      if (!more)
        checks::write_verdict_files(c.output, "all", verdicts, c.name, 0.0, question_of(c, o));
      throw_if_stop_requested("until-decided.json");
      write_state(c, s);
      if (!more) fmt::print("until-decided: {}\n", s.outcome);
    } else if (run.shards > 1) {
      // Shard 1 judges: wait for its state to move past this look.
      for (;;) {
        const State now = read_state(c);
        if (now.finished || static_cast<int>(now.looks.size()) > looks_before) {
          more = now.finished ? 0 : 1;
          break;
        }
        if (!sleep_unless_stopped(o.poll_seconds)) return 130;
      }
    }
    more = broadcast_from_root({more}).front();
    if (!more) break;
  }
  if (!decider) return 0;
  if (verdicts.empty()) {
    // Finished before this invocation: the stored verdicts are the result.
    fmt::print("until-decided: {} (verdicts in {}/checks.json)\n", read_state(c).outcome, c.output);
    return stored_exit_status(c);
  }
  return checks::exit_status(verdicts);
}

}  // namespace

int run_until_decided(const Campaign& c, const CampaignRunOptions& run,
                      const UntilDecidedOptions& o, const Ranks& ranks) {
  validate_until_decided(o);
  // The first SIGINT or SIGTERM stops it between runs (the runs by their checkpoints) or
  // between a look's stages, with nothing of the look written: run again, it goes on.
  install_stop_handlers();
  try {
    return run_looks(c, run, o, ranks);
  } catch (const Interrupted& e) {
    std::fflush(stdout);
    fmt::print(stderr, "until-decided: {}; run it again to go on\n", e.what());
    return 130;
  }
}

}  // namespace jam::design
