#pragma once
#include <CLI/CLI.hpp>

#include "sim/run/sim_config.hpp"

namespace jam {

/// Registers `jam sim` and its options on app; the callback runs the compression.
void add_sim_command(CLI::App& app, SimConfig& config);

/// Runs `jam sim` with a parsed config and prints the summary. Returns the exit status.
int run_sim_command(const SimConfig& config);

}  // namespace jam
