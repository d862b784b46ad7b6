#include "app/until_decided.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "app/check_command.hpp"
#include "app/stats_command.hpp"
#include "app/until_decided_options.hpp"
#include "campaign/added_samples.hpp"
#include "campaign/campaign_dir.hpp"
#include "campaign/run_plan.hpp"
#include "checks/check_registry.hpp"
#include "checks/checks.hpp"
#include "checks/sequential.hpp"
#include "checks/verdict_ensembles.hpp"
#include "checks/verdict_file.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---- what a verdict compares -------------------------------------------------------------

/// The ensembles more samples of which would help decide the verdict, as its check declares
/// them (empty: nothing more samples could change, e.g. a fit's verdict).
std::vector<EnsembleId> ensembles_concerned(const checks::Verdict& v) {
  return checks::samples_of(v).ensembles(v.values);
}

// ---- the state -----------------------------------------------------------------------------

struct State {
  json looks = json::array();     // {look, alpha, decided, undecided, core_seconds}
  json decided = json::object();  // key -> {look, verdict (checks.json form)}
  SampleCounts next;              // the samples the runs of the next look need
  bool finished = false;
  std::string outcome;
  json options;  // what its looks are judged with (until_decided_options.hpp); null: not recorded
};

std::string state_path(const Campaign& c) {
  return (fs::path(c.output) / "until-decided.json").string();
}

State read_state(const Campaign& c) {
  State s;
  const std::string path = state_path(c);
  if (!fs::exists(fs::symlink_status(path))) return s;
  check_input_file("until-decided state", path);
  std::ifstream in(path);
  json j;
  try {
    j = json::parse(in);
    s.looks = j.at("looks");
    s.decided = j.at("decided");
    s.finished = j.at("finished").get<bool>();
    s.outcome = j.at("outcome").get<std::string>();
    s.options = j.value("options", json());
    for (const auto& e : j.at("samples")) {
      s.next[{e.at("n").get<std::int64_t>(), e.at("phi_init").get<double>(),
              e.at("log10_rate").get<double>()}] = e.at("samples").get<std::int64_t>();
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not an until-decided state ({})", path, e.what()));
  }
  if (!s.looks.is_array() || !s.decided.is_object())
    throw std::runtime_error(fmt::format("{}: not an until-decided state", path));
  return s;
}

void write_state(const Campaign& c, const State& s) {
  json samples = json::array();
  for (const auto& [id, count] : s.next) {
    samples.push_back({{"n", id.n},
                       {"phi_init", id.phi_init},
                       {"log10_rate", id.log10_rate},
                       {"samples", count}});
  }
  const json j{{"looks", s.looks},       {"decided", s.decided}, {"samples", samples},
               {"finished", s.finished}, {"outcome", s.outcome}, {"options", s.options}};
  AtomicFile out(state_path(c));
  std::fputs((j.dump(1) + "\n").c_str(), out.stream());
  out.commit();
  // The planners' file follows the state (never the other way round): resuming rewrites it.
  write_added_samples(c, s.next);
}

// ---- cost ----------------------------------------------------------------------------------

struct Cost {
  double spent_seconds = 0;       // recorded core-seconds (CPU) of the done runs
  double seconds_per_step = NAN;  // measured: spent / their estimated particle-steps
  std::set<std::string> done;     // the runs done (each file verified once per look)
};

Cost measured_cost(const std::vector<PlannedRun>& plan) {
  Cost c;
  double steps = 0;
  for (const auto& run : plan) {
    if (run_status(run) != RunStatus::kDone) continue;
    c.done.insert(run.name);
    if (const auto w = recorded_core_seconds(run)) {
      c.spent_seconds += *w;
      steps += run.estimated_particle_steps;
    }
  }
  if (steps > 0) c.seconds_per_step = c.spent_seconds / steps;
  return c;
}

/// Estimated core-seconds of the runs a plan with `counts` adds to what is done.
double batch_seconds(const Campaign& c, const SampleCounts& counts, const Cost& cost) {
  double steps = 0;
  for (const auto& run : plan_runs(c, counts))
    if (!cost.done.count(run.name)) steps += run.estimated_particle_steps;
  return steps * cost.seconds_per_step;
}

/// The exit status of the stored checks.json (a sequence finished by an earlier invocation).
int stored_exit_status(const Campaign& c) {
  return checks::exit_status(
      checks::read_verdict_file((fs::path(c.output) / "checks.json").string()).verdicts);
}

// ---- one look ------------------------------------------------------------------------------

/// The checks' options of a look but its alpha (sequence_check_options), the range asked said
/// to come from the command line where --phi-min/--phi-max gave it.
checks::CheckOptions look_options(const Campaign& c, const UntilDecidedOptions& o,
                                  const CampaignQuestion& q) {
  checks::CheckOptions options = sequence_check_options(c, q);
  if (o.phi_min || o.phi_max)
    options.regions.asked_from = o.phi_min && o.phi_max
                                     ? "--phi-min, --phi-max"
                                     : "[question] phi_min, phi_max with --phi-min or --phi-max";
  return options;
}

/// A verdict of a range the compared data do not cover (a region at constant Z where no Z of
/// both sets has its mean packing, say): more samples of the same runs never reach it. Judged
/// by the words judge_by_region (checks/pooled_verdict.cpp) gives it.
bool uncovered(const checks::Verdict& v) {
  return v.status == "inconclusive" && (v.reason.starts_with("nothing to judge") ||
                                        v.reason.starts_with("fewer than 2 common points in"));
}

/// " over the range asked, phi in [0.83, 0.85]" when the question states one.
std::string asked_words(const CampaignQuestion& q) {
  return q.states_range()
             ? fmt::format(" over the range asked, phi in [{:g}, {:g}]", *q.phi_min, *q.phi_max)
             : std::string();
}

/// The verdicts of a look: the statistical checks of `all`, or those the question wants.
std::vector<checks::Verdict> judge_question(const Campaign& c, const CampaignQuestion& q,
                                            const checks::CheckOptions& options) {
  const checks::StatsData stats = checks::read_stats(c.output);
  if (q.checks.empty()) return checks::run_check("all", stats, options);
  std::vector<checks::Verdict> out;
  for (const std::string& name : checks_to_run(q.checks)) {
    const checks::CheckEntry* e = checks::find_check(name);
    if (!e || !std::holds_alternative<checks::StatsCheck>(e->run)) continue;
    for (auto& v : checks::run_check(name, stats, options))
      if (question_wants(q.checks, v.check)) out.push_back(std::move(v));
  }
  return out;
}

/// Judges the look, updates the state, and says whether another look follows.
bool judge_look(const Campaign& c, const UntilDecidedOptions& o, State& s,
                std::vector<checks::Verdict>* final_verdicts) {
  throw_if_stop_requested("stats.h5");  // a stop while the runs ended: no look is judged
  const int look = static_cast<int>(s.looks.size()) + 1;
  const double alpha = checks::look_alpha(o.alpha, look);
  StatsArgs stats;
  stats.directory = c.output;
  if (const int status = run_stats_command(stats); status != 0)
    throw std::runtime_error(fmt::format("until-decided: jam stats exited {}", status));
  // The campaign's margins and regions, and the question (recorded in the state:
  // until_decided_options.hpp).
  const CampaignQuestion question = sequence_question(c, o);
  checks::CheckOptions options = look_options(c, o, question);
  options.alpha = alpha;
  // Undecided verdicts are judged again at the next look's alpha: the samples aim at it.
  options.estimate_alpha = checks::look_alpha(o.alpha, look + 1);
  std::vector<checks::Verdict> verdicts = judge_question(c, question, options);
  // A stop asked for while judging: the look is judged again when the command is run again.
  throw_if_stop_requested("until-decided.json");

  // Verdicts decided at an earlier look stand; the others are this look's.
  std::vector<checks::Verdict> merged;
  SampleCounts next = samples_per_ensemble(c, s.next);
  const SampleCounts present = next;
  int decided = 0, undecided = 0, not_by_samples = 0, not_asked = 0;
  for (auto& v : verdicts) {
    const std::string key = checks::verdict_identity(v);
    if (s.decided.contains(key)) {
      // The verdict of the look that decided it; its curves are this look's data.
      const json& d = s.decided[key];
      v.status = d.at("status").get<std::string>();
      v.reason = d.at("reason").get<std::string>();
      for (auto [field, value] : {std::pair{"statistic", &v.statistic},
                                  {"threshold", &v.threshold},
                                  {"excluded_above", &v.excluded_above},
                                  {"excluded_below", &v.excluded_below},
                                  {"estimate", &v.estimate},
                                  {"detectable", &v.detectable}}) {
        *value = d.contains(field) && d.at(field).is_number() ? d.at(field).get<double>() : NAN;
      }
      v.samples_needed = NAN;
      v.values["look"] = d.at("look").get<double>();
      merged.push_back(v);
      ++decided;
      continue;
    }
    v.values["look"] = look;
    v.values["look_alpha"] = alpha;
    if (v.status != "inconclusive") {
      v.reason += fmt::format(" [look {}, alpha {:.3g}]", look, alpha);
      auto number = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
      s.decided[key] = {{"look", look},
                        {"status", v.status},
                        {"reason", v.reason},
                        {"statistic", number(v.statistic)},
                        {"threshold", number(v.threshold)},
                        {"excluded_above", number(v.excluded_above)},
                        {"excluded_below", number(v.excluded_below)},
                        {"estimate", number(v.estimate)},
                        {"detectable", number(v.detectable)}};
      ++decided;
    } else if (question.states_range() && v.region != "asked") {
      ++not_asked;  // judged and reported, but the samples go where the question is
    } else if (const auto ens = ensembles_concerned(v); ens.empty() || uncovered(v)) {
      ++not_by_samples;
    } else {
      ++undecided;
      for (std::size_t i = 0; i < ens.size(); ++i) {
        const auto id = campaign_ensemble(c, ens[i]);
        if (!id) continue;
        auto& n = next[*id];
        // The cheapest split when the verdict names one (the larger, costlier size gets
        // fewer), else the same samples for both sets.
        const auto split = v.values.find(i == 0 ? "samples_needed_a" : "samples_needed_b");
        n = std::max(n, split != v.values.end() && i < 2
                            ? checks::next_samples_of_set(present.at(*id), split->second)
                            : checks::next_samples(present.at(*id), v.samples_needed));
      }
    }
    merged.push_back(v);
  }
  *final_verdicts = merged;
  const std::vector<PlannedRun> plan = plan_runs(c);
  const Cost cost = measured_cost(plan);
  s.looks.push_back({{"look", look},
                     {"alpha", alpha},
                     {"decided", decided},
                     {"undecided", undecided},
                     {"not_decidable_by_samples", not_by_samples},
                     {"undecided_outside_the_range_asked", not_asked},
                     {"core_seconds", cost.spent_seconds}});
  const double budget = o.budget_core_hours * 3600.0;
  fmt::print(
      "until-decided: look {} at alpha {:.3g}{}: {} decided, {} undecided{}{}; {:.2f} of "
      "{:.2f} core-hours spent\n",
      look, alpha, asked_words(question), decided, undecided,
      not_by_samples ? fmt::format(", {} that samples cannot decide", not_by_samples) : "",
      not_asked ? fmt::format(", {} outside the range asked left as they stand", not_asked) : "",
      cost.spent_seconds / 3600, o.budget_core_hours);
  if (undecided == 0) {
    s.finished = true;
    s.outcome = question.states_range()
                    ? fmt::format("every verdict of the range asked decided at look {}", look)
                    : fmt::format("every verdict decided at look {}", look);
    return false;
  }
  // The next batch, shrunk until it fits what is left of the budget.
  SampleCounts batch = next;
  for (double share : {1.0, 0.5, 0.25}) {
    batch = present;
    for (const auto& [id, want] : next) {
      const auto have = present.at(id);
      batch[id] =
          have + static_cast<std::int64_t>(std::ceil(share * static_cast<double>(want - have)));
    }
    const double seconds = batch_seconds(c, batch, cost);
    if (std::isfinite(seconds) && cost.spent_seconds + seconds <= budget) {
      fmt::print(
          "until-decided: adding samples to {} ensembles (about {:.2f} core-hours)\n",
          [&] {
            int k = 0;
            for (const auto& [id, want] : batch) k += want > present.at(id);
            return k;
          }(),
          seconds / 3600);
      s.next = batch;
      return true;
    }
  }
  s.finished = true;
  s.outcome = fmt::format(
      "budget spent at look {}: {} verdicts undecided; the next batch would exceed the {:g} "
      "core-hours",
      look, undecided, o.budget_core_hours);
  return false;
}

/// What checks.json records of a sequence: the question it judged (checks.json "question":
/// the range asked, the checks, each margin, the sequence's alpha).
json question_of(const Campaign& c, const UntilDecidedOptions& o) {
  const CampaignQuestion q = sequence_question(c, o);
  checks::CheckOptions options = look_options(c, o, q);
  options.alpha = o.alpha;
  return {{"question", question_record(q, options)}, {"until_decided", true}};
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
  CampaignQuestion q = c.question;
  if (!o.phi_min && !o.phi_max) return q;
  if (!q.states_range() && !(o.phi_min && o.phi_max))
    throw std::invalid_argument(fmt::format(
        "{} {:g}: the campaign file states no range ([question] phi_min, phi_max) to take the "
        "other end from; give both --phi-min and --phi-max",
        o.phi_min ? "--phi-min" : "--phi-max", o.phi_min ? *o.phi_min : *o.phi_max));
  for (const auto& [flag, value] : {std::pair{"--phi-min", o.phi_min}, {"--phi-max", o.phi_max}})
    if (value && !(*value > 0 && *value < 1))
      throw std::invalid_argument(
          fmt::format("{} {:g}: must be a packing in (0, 1)", flag, *value));
  q.phi_min = o.phi_min ? o.phi_min : q.phi_min;
  q.phi_max = o.phi_max ? o.phi_max : q.phi_max;
  if (!(*q.phi_min < *q.phi_max))
    throw std::invalid_argument(
        fmt::format("--phi-max {:g}: must exceed phi_min {:g}", *q.phi_max, *q.phi_min));
  return q;
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

}  // namespace jam
