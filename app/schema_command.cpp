#include "app/schema_command.hpp"

#include <fmt/format.h>

#include "sim/io/open_run_schema.hpp"

namespace jam {

void add_schema_command(CLI::App& app, SchemaArgs& args) {
  CLI::App* s = app.add_subcommand(
      "schema",
      "Print the machine-readable schema (TOML) of a file format as this jam validates it: "
      "fields, types, shapes, units, allowed values (contact laws and integrators from its own "
      "registry) and limits; reference/schema/<format>.toml is its output");
  s->add_option("FORMAT", args.format, "open-run (open runs and frames files)")
      ->required()
      ->check(CLI::IsMember({"open-run"}));
}

int run_schema_command(const SchemaArgs& args) {
  if (args.format == "open-run") fmt::print("{}", open_run_schema_toml());
  return 0;
}

}  // namespace jam
