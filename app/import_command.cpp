#include "app/import_command.hpp"

#include <fmt/format.h>

#include "sim/io/output_path.hpp"

namespace jam {

void add_import_command(CLI::App& app, LammpsImport& r) {
  CLI::App* imp = app.add_subcommand("import", "Turn runs of other simulators into run files");
  imp->require_subcommand(1);
  CLI::App* lmp = imp->add_subcommand(
      "lammps", "A LAMMPS log of reference/lammps/compress_inertial.in -> run file (same schema)");
  lmp->add_option("log", r.log, "LAMMPS log (thermo: Step Time c_virial PotEng v_Z)")->required();
  lmp->add_option("--data", r.data, "The LAMMPS data file the run started from")->required();
  lmp->add_option("--out", r.out, "Run file to write (HDF5)")->required();
}

int run_import_command(const LammpsImport& request) {
  LammpsImport r = request;
  r.out = checked_output_file("out", r.out);
  import_lammps_run(r);
  fmt::print("wrote {}\n", r.out);
  return 0;
}

}  // namespace jam
