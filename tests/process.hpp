#pragma once
// Child processes for the tests that kill runs: spawn jam with its output discarded, wait,
// and read files whole.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace jam::test {

/// Starts `jam <args>` (args split on blanks) with stdout and stderr sent to /dev/null.
inline pid_t spawn_jam(const std::string& args) {
  std::vector<std::string> words = {JAM_EXECUTABLE};
  std::istringstream in(args);
  for (std::string w; in >> w;) words.push_back(w);
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + words[0]);
  return pid;
}

/// Exit status, or minus the signal that ended the process.
inline int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

struct Outcome {
  int status;  // exit status, -1 when killed
  std::string output;  // stdout and stderr together
};

/// Runs `jam <args>` through the shell and waits; its output goes through `log`. `prefix` is
/// put before the command (ulimit, traps).
inline Outcome run_jam_logged(const std::filesystem::path& log, const std::string& args,
                              const std::string& prefix = "") {
  const std::string cmd = "sh -c '" + prefix + std::string(JAM_EXECUTABLE) + " " + args + " > " +
                          log.string() + " 2>&1'";
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(log)};
}

}  // namespace jam::test
