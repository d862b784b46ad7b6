#pragma once
// The judging options' table (design/judging_options.hpp) declared to a command line: `jam
// check` and `jam pipeline` both take them from it.
#include <CLI/CLI.hpp>

#include "design/judging_options.hpp"

namespace jam {

/// Adds the table's options to a command.
void add_judging_options(CLI::App* command, design::JudgingArgs& args);

}  // namespace jam
