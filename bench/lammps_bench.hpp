#pragma once
// LAMMPS as the baseline of `jam bench`: reference/lammps/bench_compress.in (the model of
// compress_inertial.in with only the virial pressure in the thermo) run on a data file written
// by jam, on one or more MPI ranks, and its log read back: the loop time LAMMPS reports (the
// dynamics only, without reading the data file), its memory and the thermo pressures.
#include <filesystem>
#include <string>
#include <vector>

namespace jam::bench {

bool lmp_available();

struct LammpsRequest {
  std::filesystem::path directory;  // where the inputs are copied and the log is written
  std::filesystem::path reference;  // reference/lammps
  std::string data;                 // data file name inside directory
  std::string log;                  // log file name inside directory
  int dim = 2;
  double rate = 1e-4, dt = 0.01;
  long steps = 100, every = 100;
  int ranks = 1;  // MPI ranks (mpirun -np) for one run
};

struct LammpsResult {
  double loop_seconds = 0.0;  // "Loop time of X on P procs for S steps with N atoms"
  long steps = 0, atoms = 0;
  int procs = 0;
  double memory_mbytes = 0.0;  // "Per MPI rank memory allocation (min/avg/max)": the maximum
  std::vector<double> step, time, pressure;
};

/// The argument vector that runs the request (lmp, or mpirun -np R lmp); no shell.
std::vector<std::string> lammps_command(const LammpsRequest& r);

/// Copies the input and table next to the data file (safely while other runs in the same
/// directory do the same), runs LAMMPS, reads the log; throws on failure with the command.
LammpsResult run_lammps(const LammpsRequest& r);

/// Reads a log of bench_compress.in; throws naming the file when something is missing.
LammpsResult read_lammps_log(const std::filesystem::path& log);

}  // namespace jam::bench
