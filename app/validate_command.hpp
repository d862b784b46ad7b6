#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace jam {

struct ValidateArgs {
  std::vector<std::string> runs;
  bool checks = false;  // --checks: the files are verdict files (checks.json)
  bool stats = false;   // --stats: the files are statistics (stats.h5)
};

/// Registers `jam validate RUN...`: each file read and checked as the open run format says
/// (the same rules as `jam campaign import` and jamio.validate_run), one line per file.
void add_validate_command(CLI::App& app, ValidateArgs& args);

/// 0 when every file is a valid run (with --checks: a valid checks.json; with --stats: a valid
/// stats.h5), 1 when one is not (its reason printed), 2 on bad input.
int run_validate_command(const ValidateArgs& args);

}  // namespace jam
