#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "sim/io/lammps_import.hpp"

namespace jam {

/// What `jam import` was asked: a LAMMPS log (of the bundled input, or of any input with its
/// columns named), or configuration frames whose observables jam measures itself.
struct ImportRequest {
  LammpsImport lammps;
  std::vector<std::string> columns;  // FIELD=COLUMN, parsed into lammps.columns
  std::string frames, frames_out;
  CLI::App* lammps_command = nullptr;
  CLI::App* frames_command = nullptr;
};

/// Registers `jam import lammps LOG ...` and `jam import frames FRAMES --out run.h5`.
void add_import_command(CLI::App& app, ImportRequest& request);

int run_import_command(ImportRequest& request);

}  // namespace jam
