#pragma once
#include <CLI/CLI.hpp>

#include "sim/io/lammps_import.hpp"

namespace jam {

/// Registers `jam import lammps LOG --data INIT.data --out run.h5`.
void add_import_command(CLI::App& app, LammpsImport& request);

int run_import_command(const LammpsImport& request);

}  // namespace jam
