#include "bench/lammps_bench.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/io/lammps_data.hpp"
#include "sim/io/lammps_log.hpp"
#include "sim/io/lammps_table.hpp"
#include "sim/io/process.hpp"
#include "sim/model/species.hpp"

namespace jam::bench {
namespace fs = std::filesystem;

bool lmp_available() {
  return !find_program("lmp").empty();
}

std::vector<std::string> lammps_command(const LammpsRequest& r) {
  std::vector<std::string> argv;
  if (r.ranks > 1) {
    argv = {"mpirun", "--allow-run-as-root", "--oversubscribe", "-np", std::to_string(r.ranks)};
  }
  auto g = [](double v) { return fmt::format("{:.17g}", v); };
  auto variables = lammps_species_variables(r.dim);
  variables.insert(variables.begin(), {{"data", r.data},
                                       {"table", "harmonic_contact.table"},
                                       {"table_style", HarmonicContact::kLammpsTableStyle},
                                       {"dim", std::to_string(r.dim)},
                                       {"rate", g(r.rate)},
                                       {"dt", g(r.dt)},
                                       {"steps", std::to_string(r.steps)},
                                       {"every", std::to_string(r.every)}});
  const auto lmp = lammps_command_line(r.log, "bench_compress.in", variables);
  argv.insert(argv.end(), lmp.begin(), lmp.end());
  return argv;
}

LammpsResult run_lammps(const LammpsRequest& r) {
  // Runs at the same time share the directory: each copies the inputs under a name of its own
  // (its log's) and renames the copy into place, an atomic replacement, so that no run ever
  // reads an input another is in the middle of writing (they are the same files).
  const fs::path input_copy = r.directory / ("bench_compress.in." + r.log + ".partial");
  fs::copy_file(r.reference / "bench_compress.in", input_copy,
                fs::copy_options::overwrite_existing);
  fs::rename(input_copy, r.directory / "bench_compress.in");
  const LammpsTableFile table = lammps_table_for("harmonic", kPaperDiameterRatio);
  const fs::path table_copy = r.directory / (table.file + "." + r.log + ".partial");
  std::ofstream(table_copy) << table.text;
  fs::rename(table_copy, r.directory / table.file);
  run_lammps_process(lammps_command(r), r.directory, r.log);
  return read_lammps_log(r.directory / r.log);
}

LammpsResult read_lammps_log(const fs::path& log) {
  std::ifstream in(log);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read LAMMPS log", log.string()));
  LammpsResult res;
  bool in_thermo = false;
  for (std::string line; std::getline(in, line);) {
    std::istringstream w(line);
    std::string first;
    w >> first;
    if (first == "Step") {
      in_thermo = true;
      continue;
    }
    if (first == "Loop") {
      // Loop time of 1.234 on 1 procs for 100 steps with 4096 atoms
      std::string time, of, on, procs, for_, steps, with;
      w >> time >> of >> res.loop_seconds >> on >> res.procs >> procs >> for_ >> res.steps >>
          steps >> with >> res.atoms;
      in_thermo = false;
      continue;
    }
    if (line.find("Per MPI rank memory allocation") != std::string::npos) {
      // Per MPI rank memory allocation (min/avg/max) = 3.1 | 3.1 | 3.1 Mbytes
      const auto eq = line.find('=');
      std::istringstream m(line.substr(eq + 1));
      double a = 0, b = 0, c = 0;
      std::string bar;
      m >> a >> bar >> b >> bar >> c;
      res.memory_mbytes = c;
      continue;
    }
    if (!in_thermo) continue;
    std::istringstream t(line);
    double step = 0, time = 0, p = 0;
    if (t >> step >> time >> p) {
      res.step.push_back(step);
      res.time.push_back(time);
      res.pressure.push_back(p);
    } else {
      in_thermo = false;
    }
  }
  if (!(res.loop_seconds > 0) || res.steps <= 0 || res.atoms <= 0) {
    throw std::runtime_error(fmt::format("{}: no 'Loop time' line (LAMMPS failed?)", log.string()));
  }
  return res;
}

}  // namespace jam::bench
