#pragma once
// The check stage as the stages above it run it (`jam check NAME DIR`, `jam pipeline`): the
// campaign file's judging settings read, the registry's checks run on DIR/stats.h5 (the
// question's only, when it names checks; compare_with's campaigns judged against it), the
// verdicts printed and written whole to DIR/checks.{json,xml,h5} (checks/verdict_file.hpp)
// with the record of what they were judged with (check_record), which tells `jam pipeline`
// whether to judge again. Option parsing stays in app/check_command.cpp.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "checks/regression_check.hpp"
#include "design/judging_options.hpp"

namespace jam::design {

/// What `jam check NAME DIR` judges.
struct CheckRequest {
  std::string name, directory, set_a, set_b;
  JudgingArgs judging;  // the options `jam pipeline` shares (judging_options.hpp)
  bool regenerate = false;
  bool table = true;    // print the verdict table (the main job leaves it to the report)
  std::string against;  // regression: baseline directory
  checks::RegressionOptions regression;
};

/// Runs the check, prints the table, writes DIR/checks.{json,xml,h5} (`all`) or
/// DIR/checks-NAME.{json,xml,h5}; returns checks::exit_status (0 pass, 1 fail, 3 inconclusive).
/// Throws, one line, on a bad option, a missing directory or an out-of-date stats.h5.
int run_check_stage(const CheckRequest& request);

/// The checks `jam check all` runs by name for a campaign whose [question] names `wanted`
/// (a part, e.g. jamming_point, through the check that writes it), in the registry's order;
/// compare stays with compare_with.
std::vector<std::string> checks_to_run(const std::vector<std::string>& wanted);

/// Whether a verdict of `check` answers the question (every check when `wanted` is empty; a
/// part when its check is wanted).
bool question_wants(const std::vector<std::string>& wanted, const std::string& check);

/// What `jam check NAME DIR` judges with: DIR/campaign.toml's margins (when there is one), then
/// the options given; the record checks.json keeps of them. Throws naming a bad option.
nlohmann::json check_record(const CheckRequest& request);

}  // namespace jam::design
