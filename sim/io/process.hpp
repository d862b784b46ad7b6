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
};

/// Runs argv[0] (looked up on PATH when it holds no '/') with the arguments argv and waits.
/// Returns its exit status, or 128 + the signal that ended it. Throws std::runtime_error
/// naming the program when it cannot be started at all.
int run_program(const std::vector<std::string>& argv, const ProcessOptions& options = {});

/// The full path of an executable program on PATH, or "" when there is none (what the shell's
/// `command -v` finds, without a shell).
std::string find_program(const std::string& name);

}  // namespace jam
