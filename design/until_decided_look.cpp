#include "design/until_decided_look.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "campaign/run_plan.hpp"
#include "checks/check_registry.hpp"
#include "checks/checks.hpp"
#include "checks/sequential.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict_ensembles.hpp"
#include "design/check_stage.hpp"
#include "design/judging_options.hpp"
#include "design/sequence_cost.hpp"
#include "design/stats_stage.hpp"
#include "design/until_decided_options.hpp"
#include "sim/run/stop_signal.hpp"

namespace jam::design {
namespace {

/// The checks' options of a look but its alpha (sequence_check_options), the range asked said
/// to come from the command line where --phi-min/--phi-max gave it.
checks::CheckOptions look_options(const Campaign& c, const UntilDecidedOptions& o,
                                  const CampaignQuestion& question) {
  checks::CheckOptions options = sequence_check_options(c, question);
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
std::string asked_words(const CampaignQuestion& question) {
  return question.states_range() ? fmt::format(" over the range asked, phi in [{:g}, {:g}]",
                                               *question.phi_min, *question.phi_max)
                                 : std::string();
}

/// The verdicts of a look: the statistical checks of `all`, or those the question wants.
std::vector<checks::Verdict> judge_question(const Campaign& c, const CampaignQuestion& question,
                                            const checks::CheckOptions& options) {
  const checks::StatsData stats = checks::read_stats(c.output);
  if (question.checks.empty()) return checks::run_check("all", stats, options);
  std::vector<checks::Verdict> out;
  for (const std::string& name : checks_to_run(question.checks)) {
    const checks::CheckEntry* e = checks::find_check(name);
    if (!e || !std::holds_alternative<checks::StatsCheck>(e->run)) continue;
    for (auto& v : checks::run_check(name, stats, options))
      if (question_wants(question.checks, v.check)) out.push_back(std::move(v));
  }
  return out;
}

/// What a look made of its verdicts.
struct Tally {
  int decided = 0, undecided = 0, not_by_samples = 0, not_asked = 0;
};

/// Asks for the samples the undecided verdict `v` needs of the ensembles it concerns (`ens`,
/// as its check declares them), on top of those `present`.
void ask_samples(const Campaign& c, const checks::Verdict& v, const std::vector<EnsembleId>& ens,
                 const SampleCounts& present, SampleCounts& next) {
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

/// Verdicts decided at an earlier look stand; the others are this look's: decided now
/// (recorded in the state), or undecided, their samples asked for in `next`.
Tally merge_look(const Campaign& c, const CampaignQuestion& question, int look, double alpha,
                 State& s, std::vector<checks::Verdict>& verdicts, const SampleCounts& present,
                 SampleCounts& next) {
  Tally t;
  for (auto& v : verdicts) {
    const std::string key = checks::verdict_identity(v);
    if (s.decided.contains(key)) {
      restore_decided(s.decided[key], v);
      ++t.decided;
      continue;
    }
    v.values["look"] = look;
    v.values["look_alpha"] = alpha;
    if (v.status != "inconclusive") {
      v.reason += fmt::format(" [look {}, alpha {:.3g}]", look, alpha);
      record_decided(s, key, v, look);
      ++t.decided;
    } else if (question.states_range() && v.region != "asked") {
      ++t.not_asked;  // judged and reported, but the samples go where the question is
    } else if (const auto ens = checks::samples_of(v).ensembles(v.values);
               ens.empty() || uncovered(v)) {
      ++t.not_by_samples;  // e.g. a fit's verdict: nothing more samples could change
    } else {
      ++t.undecided;
      ask_samples(c, v, ens, present, next);
    }
  }
  return t;
}

/// The next batch, shrunk until it fits what is left of the budget, into the state; false
/// (the state finished) when even a quarter of it would not.
bool plan_next_batch(const Campaign& c, const UntilDecidedOptions& o, State& s, int look,
                     int undecided, const SampleCounts& present, const SampleCounts& next,
                     const Cost& cost) {
  const double budget = o.budget_core_hours * 3600.0;
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
      int grown = 0;
      for (const auto& [id, want] : batch) grown += want > present.at(id);
      fmt::print("until-decided: adding samples to {} ensembles (about {:.2f} core-hours)\n", grown,
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

}  // namespace

bool judge_look(const Campaign& c, const UntilDecidedOptions& o, State& s,
                std::vector<checks::Verdict>* final_verdicts) {
  throw_if_stop_requested("stats.h5");  // a stop while the runs ended: no look is judged
  const int look = static_cast<int>(s.looks.size()) + 1;
  const double alpha = checks::look_alpha(o.alpha, look);
  average_campaign(c.output);  // as `jam stats DIR`
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

  SampleCounts next = samples_per_ensemble(c, s.next);
  const SampleCounts present = next;
  const Tally t = merge_look(c, question, look, alpha, s, verdicts, present, next);
  *final_verdicts = verdicts;
  const Cost cost = measured_cost(plan_runs(c));
  s.looks.push_back({{"look", look},
                     {"alpha", alpha},
                     {"decided", t.decided},
                     {"undecided", t.undecided},
                     {"not_decidable_by_samples", t.not_by_samples},
                     {"undecided_outside_the_range_asked", t.not_asked},
                     {"core_seconds", cost.spent_seconds}});
  fmt::print(
      "until-decided: look {} at alpha {:.3g}{}: {} decided, {} undecided{}{}; {:.2f} of "
      "{:.2f} core-hours spent\n",
      look, alpha, asked_words(question), t.decided, t.undecided,
      t.not_by_samples ? fmt::format(", {} that samples cannot decide", t.not_by_samples) : "",
      t.not_asked ? fmt::format(", {} outside the range asked left as they stand", t.not_asked)
                  : "",
      cost.spent_seconds / 3600, o.budget_core_hours);
  if (t.undecided == 0) {
    s.finished = true;
    s.outcome = question.states_range()
                    ? fmt::format("every verdict of the range asked decided at look {}", look)
                    : fmt::format("every verdict decided at look {}", look);
    return false;
  }
  return plan_next_batch(c, o, s, look, t.undecided, present, next, cost);
}

nlohmann::json question_of(const Campaign& c, const UntilDecidedOptions& o) {
  const CampaignQuestion question = sequence_question(c, o);
  checks::CheckOptions options = look_options(c, o, question);
  options.alpha = o.alpha;
  return {{"question", question_record(question, options)}, {"until_decided", true}};
}

}  // namespace jam::design
