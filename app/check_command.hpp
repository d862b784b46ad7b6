#pragma once
#include <CLI/CLI.hpp>

#include "checks/checks.hpp"
#include "checks/lammps_check.hpp"
#include "checks/regression_check.hpp"
#include "sim/io/install_paths.hpp"

namespace jam {

struct CheckArgs {
  std::string name, directory, set_a, set_b;
  checks::CheckOptions options;
  std::optional<double> phi_min, phi_max;
  std::optional<double> margin;
  std::string reference_dir = data_path("reference").string();
  bool no_lmp = false, regenerate = false;
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

/// Writes DIR/checks.{json,xml,h5} (name "all") or DIR/checks-NAME.*, each atomically.
void write_verdict_files(const std::string& directory, const std::string& name,
                         const std::vector<checks::Verdict>& verdicts,
                         const std::string& campaign_name, double seconds);

}  // namespace jam
