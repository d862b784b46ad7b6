#pragma once
// `jam check NAME DIR`: its options; the stage itself is design/check_stage.hpp.
#include <CLI/CLI.hpp>

#include "design/check_stage.hpp"

namespace jam {

struct CheckArgs {
  design::CheckRequest check;  // what is judged, and how
  bool list_json = false;      // --list --json
};

/// Registers `jam check NAME DIR`.
void add_check_command(CLI::App& app, CheckArgs& args);

/// Runs the check stage (design::run_check_stage); returns checks::exit_status (0 pass, 1
/// fail, 3 inconclusive).
int run_check_command(const CheckArgs& args);

}  // namespace jam
