#pragma once
// Child processes (lmp, mpirun, python3) started from an argument vector with posix_spawn:
// no shell ever sees a path or a value, so a directory named `a;b` or `$(x)` is just a name.
#include <filesystem>
#include <string>
#include <vector>

namespace jam {

struct ProcessOptions {
  std::filesystem::path working_directory;  // empty: the caller's
  std::string stdout_file;                  // empty: the caller's; "/dev/null" discards
  std::string stderr_file;                  // empty: the caller's; may equal stdout_file
  // An Open MPI program (lmp, mpirun): it gets a session directory of its own, made for it and
  // removed after it (OMPI_MCA_orte_tmpdir_base, unless the caller's environment sets it).
  // Open MPI 4 programs, singletons included, otherwise share /tmp/ompi.<host>.<uid>, which
  // each removes at its end when it finds it empty; a program creating its job's directory in
  // it at that moment fails in orte_init (open-mpi/ompi#3818, #8510: concurrent MPI programs
  // under ctest -j). Two benchmark runs at once, or a Slurm job's tasks on one node, would hit
  // it at random.
  bool mpi_program = false;
  // A stop asked for while it runs (the first SIGINT or SIGTERM, sim/run/stop_signal.hpp) is
  // passed on to it as SIGINT, once, and the wait goes on until it has ended: `jam pipeline`'s
  // report stage, whose Python cleans up its temporary directory on SIGINT.
  bool pass_stop_on = false;
};

/// A new, empty directory of its own under the temporary directory, "<prefix>-XXXXXX"
/// (mkdtemp); throws WriteError naming it when it cannot be made. Whoever makes one may remove
/// it whole: it never existed before.
std::filesystem::path make_temp_directory(const std::string& prefix);

/// Runs argv[0] (looked up on PATH when it holds no '/') with the arguments argv and waits.
/// Returns its exit status, or 128 + the signal that ended it. Throws std::runtime_error
/// naming the program when it cannot be started at all.
int run_program(const std::vector<std::string>& argv, const ProcessOptions& options = {});

/// The full path of an executable program on PATH, or "" when there is none (what the shell's
/// `command -v` finds, without a shell).
std::string find_program(const std::string& name);

}  // namespace jam
