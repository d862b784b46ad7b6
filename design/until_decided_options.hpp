#pragma once
// What an --until-decided sequence is judged with, recorded in its state (until-decided.json,
// "options") when it begins: the alpha spent over its looks, each check's margin as used (the
// campaign file's [margins]), the regions (its [regions]), the range asked (its [question]
// or --phi-min/--phi-max) and the checks judged (all, or [question] checks). Its looks and
// decided verdicts hold only for these; a later invocation that would judge with others is
// refused, naming the option and both values, never handed the old verdicts.
#include <nlohmann/json.hpp>
#include <string>

#include "campaign/campaign_file.hpp"
#include "checks/checks.hpp"

namespace jam::design {

/// The checks' options of every look but its alpha: the campaign's margins and regions, as
/// `jam check all` takes them from the campaign file, and the question asked (its range
/// judged as the region "asked").
checks::CheckOptions sequence_check_options(const Campaign& c, const CampaignQuestion& question);

/// The record: {alpha, margins: {check: margin}, regions: {phi_j, near, far}, checks: [...],
/// question: {phi_min, phi_max}} (question null: no range asked).
nlohmann::json sequence_record(const Campaign& c, const CampaignQuestion& question, double alpha);

/// "" when `now` judges as `recorded` does; otherwise one line naming the first option that
/// differs, with the value now and the recorded one.
std::string sequence_difference(const nlohmann::json& recorded, const nlohmann::json& now);

}  // namespace jam::design
