#include "app/import_command.hpp"

#include <fmt/format.h>

#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/frames_import.hpp"
#include "sim/io/output_path.hpp"
#include "sim/model/contact_laws.hpp"

namespace jam {

void add_import_command(CLI::App& app, ImportRequest& r) {
  CLI::App* imp = app.add_subcommand("import", "Turn runs of other simulators into run files");
  imp->require_subcommand(1);
  CLI::App* lmp = imp->add_subcommand(
      "lammps",
      "A LAMMPS log -> run file: of any input with --column and the model's parameters (an open "
      "run, docs/cross-simulator.md), or of reference/lammps/compress_inertial.in with --data");
  r.lammps_command = lmp;
  LammpsImport& l = r.lammps;
  lmp->add_option("log", l.log, "LAMMPS log")->required();
  lmp->add_option("--out", l.out, "Run file to write (HDF5)")->required();
  lmp->add_option("--data", l.data,
                  "The start of reference/lammps/compress_inertial.in (its thermo: Step Time "
                  "c_virial PotEng v_Z); without it, name the columns");
  lmp->add_option("--column", r.columns,
                  "FIELD=COLUMN: the thermo column of a field (pressure, packing_fraction, volume, "
                  "time, step, contacts_per_particle, energy_per_particle), as LAMMPS prints it");
  lmp->add_option("--dim", l.dim, "Dimension (checked against the log's `dimension`)");
  lmp->add_option("--n", l.n, "Particles (checked against the atoms the log created or read)");
  lmp->add_option("--rate", l.rate, "Compression rate, 1/t0 (checked against fix deform trate)");
  lmp->add_option("--phi-init", l.phi_init, "Packing fraction at the first row");
  lmp->add_option("--diameter-ratio", l.diameter_ratio, "d_big / d_small of the model simulated");
  lmp->add_option("--contact", l.contact, "Contact law: " + or_list(contact_law_names()))
      ->default_str("harmonic");
  lmp->add_option("--q", l.quality_factor,
                  "Quality factor Q of an inertial run (default: overdamped)");
  lmp->add_option("--sample", l.sample, "The run's sample id in its ensemble, >= 0");
  CLI::App* frames = imp->add_subcommand(
      "frames",
      "Configuration frames (docs/cross-simulator.md) -> an open run, with p, Z and "
      "the energy measured by jam");
  r.frames_command = frames;
  frames->add_option("frames", r.frames, "Frames file (HDF5)")->required();
  frames->add_option("--out", r.frames_out, "Run file to write (HDF5)")->required();
}

int run_import_command(ImportRequest& r) {
  if (r.frames_command && r.frames_command->parsed()) {
    const std::string out = checked_output_file("out", r.frames_out);
    import_frames(r.frames, out);
    fmt::print("wrote {}\n", out);
    return 0;
  }
  LammpsImport l = r.lammps;
  l.out = checked_output_file("out", l.out);
  for (const auto& c : r.columns) {
    const auto eq = c.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == c.size())
      throw std::runtime_error(fmt::format("--column '{}': must be FIELD=COLUMN", c));
    l.columns[c.substr(0, eq)] = c.substr(eq + 1);
  }
  if (!l.data.empty()) {
    if (!l.columns.empty())
      throw std::runtime_error("--data and --column: --data reads the bundled input's log only");
    import_lammps_run(l);
  } else {
    import_lammps_log(l);
  }
  fmt::print("wrote {}\n", l.out);
  return 0;
}

}  // namespace jam
