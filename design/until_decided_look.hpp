#pragma once
// One look of an --until-decided sequence (until_decided.hpp): the campaign averaged, its
// question judged at the look's alpha, the verdicts decided at earlier looks kept, and the
// samples that the undecided ones need planned into the state, shrunk to the budget left.
#include <nlohmann/json.hpp>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "checks/verdict.hpp"
#include "design/until_decided.hpp"
#include "design/until_decided_state.hpp"

namespace jam::design {

/// Judges the look, updates the state (the look, the verdicts it decided, the next samples or
/// the outcome), puts the look's verdicts in `verdicts` and says whether another look follows.
bool judge_look(const Campaign& c, const UntilDecidedOptions& o, State& s,
                std::vector<checks::Verdict>* verdicts);

/// What checks.json records of a sequence: the question it judged (checks.json "question":
/// the range asked, the checks, each margin, the sequence's alpha) and "until_decided".
nlohmann::json question_of(const Campaign& c, const UntilDecidedOptions& o);

}  // namespace jam::design
