#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace jam {

struct SchemaArgs {
  std::string format;
};

/// Registers `jam schema FORMAT`: the machine-readable schema of a file format, written from
/// the tables this jam validates with (open-run: reference/schema/open_run.toml).
void add_schema_command(CLI::App& app, SchemaArgs& args);

/// Prints the schema to standard output; 0.
int run_schema_command(const SchemaArgs& args);

}  // namespace jam
