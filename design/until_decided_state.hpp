#pragma once
// The state of an --until-decided sequence, <output>/until-decided.json: the looks so far, the
// verdicts decided and at which look (each in its checks.json form, checks/verdict_file.hpp),
// the samples per ensemble the next runs need, whether it finished and how, and the options it
// is judged with (until_decided_options.hpp). Written atomically, then added-samples.toml
// (what the planners read, campaign/added_samples.hpp) from it.
#include <nlohmann/json.hpp>
#include <string>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_file.hpp"
#include "checks/verdict.hpp"

namespace jam::design {

struct State {
  nlohmann::json looks = nlohmann::json::array();     // {look, alpha, decided, undecided, ...}
  nlohmann::json decided = nlohmann::json::object();  // identity -> verdict, with its "look"
  SampleCounts next;                                  // the samples the runs of the next look need
  bool finished = false;
  std::string outcome;
  nlohmann::json options;  // what its looks are judged with; null: not recorded
};

/// <output>/until-decided.json.
std::string state_path(const Campaign& c);

/// The state; an empty one when there is none. Throws naming the file when it is not a state.
State read_state(const Campaign& c);

/// Writes the state, then added-samples.toml from it (never the other way round: resuming
/// rewrites the planners' file).
void write_state(const Campaign& c, const State& s);

/// Records `v` as decided at `look` under `identity` (checks::verdict_identity): its
/// checks.json form (checks::verdict_json) and "look".
void record_decided(State& s, const std::string& identity, const checks::Verdict& v, int look);

/// `v` (this look's verdict of the same identity) as the look that decided it judged it: its
/// status, reason and numbers from `decided`, its "look" among its values; its curves stay
/// this look's data. Reads the states of earlier jams too (their "detectable").
void restore_decided(const nlohmann::json& decided, checks::Verdict& v);

}  // namespace jam::design
