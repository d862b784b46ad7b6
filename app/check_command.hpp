#pragma once
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/check_options.hpp"
#include "checks/checks.hpp"
#include "checks/lammps_check.hpp"
#include "checks/regression_check.hpp"

namespace jam {

struct CheckArgs {
  std::string name, directory, set_a, set_b;
  JudgingArgs judging;  // the options `jam pipeline` shares (check_options.hpp)
  bool regenerate = false;
  bool list_json = false;  // --list --json
  bool table = true;       // print the verdict table (the main job leaves it to the report)
  std::string against;     // regression: baseline directory
  checks::RegressionOptions regression;
};

/// Registers `jam check NAME DIR`.
void add_check_command(CLI::App& app, CheckArgs& args);

/// Runs the check, prints the table, writes DIR/checks.{json,xml,h5} (`all`) or
/// DIR/checks-NAME.{json,xml,h5}; returns checks::exit_status (0 pass, 1 fail, 3 inconclusive).
int run_check_command(const CheckArgs& args);

/// The checks `jam check all` runs by name for a campaign whose [question] names `wanted`
/// (a part, e.g. jamming_point, through the check that writes it), in the registry's order;
/// compare stays with compare_with.
std::vector<std::string> checks_to_run(const std::vector<std::string>& wanted);

/// Whether a verdict of `check` answers the question (every check when `wanted` is empty; a
/// part when its check is wanted).
bool question_wants(const std::vector<std::string>& wanted, const std::string& check);

/// What `jam check NAME DIR` judges with: DIR/campaign.toml's margins (when there is one), then
/// the options given; the record checks.json keeps of them. Throws naming a bad option.
nlohmann::json check_record(const CheckArgs& args);

}  // namespace jam
