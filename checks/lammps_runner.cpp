#include "checks/lammps_runner.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "sim/io/atomic_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/lammps_log.hpp"
#include "sim/io/lammps_table.hpp"
#include "sim/io/process.hpp"
#include "sim/model/species.hpp"
#include "sim/run/compression_run.hpp"

namespace jam::checks {
namespace fs = std::filesystem;

bool lmp_available() {
  return !find_program("lmp").empty();
}

std::string lammps_version(const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);
  return line;
}

void run_lammps(const fs::path& dir, const fs::path& reference, int dim, double rate, double dt,
                long steps, long every, const std::string& data, const std::string& log,
                const std::string& end, const std::string& contact) {
  copy_file_atomically((reference / "compress_inertial.in").string(),
                       (dir / "compress_inertial.in").string());
  // The law's own table (sim/io/lammps_table.hpp): LAMMPS runs the law jam runs.
  const LammpsTableFile table = write_lammps_table(dir, contact, kPaperDiameterRatio);
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  auto variables = lammps_species_variables(dim);
  variables.insert(variables.begin(), {{"data", data},
                                       {"table", table.file},
                                       {"table_style", table.style},
                                       {"out", end},
                                       {"dim", std::to_string(dim)},
                                       {"rate", g(rate)},
                                       {"dt", g(dt)},
                                       {"steps", std::to_string(steps)},
                                       {"every", std::to_string(every)}});
  run_lammps_process(lammps_command_line(log, "compress_inertial.in", variables), dir, log);
}

void write_relaxed_start(const StartSpec& spec, const fs::path& data) {
  SimConfig a;
  a.dim = spec.dim;
  a.n = 256;
  a.phi_init = spec.phi;
  a.phi_stop = spec.phi * 1.001;  // the start is written before any compression step
  a.compression_rate = 1e-3;
  a.dynamics = spec.dynamics;
  a.quality_factor = spec.quality_factor;
  a.dt = spec.dt;
  a.relax_energy = spec.relax_energy;
  a.seed = spec.seed;
  a.quiet = true;
  a.checkpoint_interval = 0;
  a.out = (data.parent_path() / "start_run.h5").string();
  a.write_lammps_data = data.string();
  run_compression(a);
}

}  // namespace jam::checks
