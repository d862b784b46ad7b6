#pragma once
// Child processes for the tests, started from an argument vector (jam::run_program, no shell):
// jam with its output in a file or discarded, waiting, and reading files whole.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/io/process.hpp"

extern char** environ;

namespace jam::test {

/// The words of args, split on blanks (the tests' paths have none).
inline std::vector<std::string> words(const std::string& args) {
  std::vector<std::string> w;
  std::istringstream in(args);
  for (std::string word; in >> word;) w.push_back(word);
  return w;
}

/// argv of `jam <args>`.
inline std::vector<std::string> jam_argv(const std::string& args) {
  std::vector<std::string> argv = {JAM_EXECUTABLE};
  for (auto& w : words(args)) argv.push_back(w);
  return argv;
}

/// Starts `jam <args>` with stdout and stderr sent to /dev/null, without waiting.
inline pid_t spawn_jam(const std::string& args) {
  std::vector<std::string> argv = jam_argv(args);
  std::vector<char*> raw;
  for (auto& w : argv) raw.push_back(w.data());
  raw.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, raw[0], &actions, nullptr, raw.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + argv[0]);
  return pid;
}

/// Waits until a file in `dir` has been written after `since`, or the process has ended (then
/// false, the process left for the caller to reap), at most a minute. Tests that signal a run
/// wait for this instead of guessing how long its start takes.
inline bool wrote_since(const std::filesystem::path& dir, std::filesystem::file_time_type since,
                        pid_t pid) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
  while (std::chrono::steady_clock::now() < deadline) {
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
      if (std::filesystem::last_write_time(e.path(), ec) > since) return true;
    }
    siginfo_t info{};  // WNOWAIT: ended or not, the process stays to be reaped by wait_for
    if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
        info.si_pid == pid) {
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// Waits (at most two minutes) until `ready()` or the process has ended; true when ready.
template <class Ready>
bool wait_until(Ready ready, pid_t pid) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (std::chrono::steady_clock::now() < deadline) {
    if (ready()) return true;
    siginfo_t info{};  // WNOWAIT: the process stays to be reaped by wait_for
    if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
        info.si_pid == pid)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return false;
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
  int status;          // exit status; 128 + the signal when killed
  std::string output;  // stdout and stderr together
};

/// Runs argv and waits; its stdout and stderr go to `log` and come back in the outcome.
inline Outcome run_logged(const std::filesystem::path& log, const std::vector<std::string>& argv) {
  jam::ProcessOptions o;
  o.stdout_file = o.stderr_file = log.string();
  const int status = jam::run_program(argv, o);
  return {status, slurp(log)};
}

/// Limits for a child: the largest file it may write (0: none). SIGXFSZ is ignored for the
/// duration, so that a write beyond the limit fails with EFBIG as on a full disk.
struct Limits {
  long file_size_bytes = 0;
};

/// Runs `jam <args>` and waits; its output goes through `log`.
inline Outcome run_jam_logged(const std::filesystem::path& log, const std::string& args,
                              const Limits& limits = {}) {
  std::vector<std::string> argv = jam_argv(args);
  if (limits.file_size_bytes > 0) {
    argv.insert(argv.begin(),
                {"prlimit", "--fsize=" + std::to_string(limits.file_size_bytes), "--"});
    auto* previous = std::signal(SIGXFSZ, SIG_IGN);  // inherited through exec
    const Outcome o = run_logged(log, argv);
    std::signal(SIGXFSZ, previous);
    return o;
  }
  return run_logged(log, argv);
}

/// Runs `jam <args>` with stdout discarded and stderr returned in the outcome.
inline Outcome run_jam_stderr(const std::filesystem::path& err, const std::string& args) {
  jam::ProcessOptions o;
  o.stdout_file = "/dev/null";
  o.stderr_file = err.string();
  const int status = jam::run_program(jam_argv(args), o);
  return {status, slurp(err)};
}

}  // namespace jam::test
