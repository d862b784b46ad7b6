#include "sim/io/process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "sim/io/atomic_file.hpp"
#include "sim/run/stop_signal.hpp"

extern char** environ;

namespace jam {
namespace {

/// posix_spawn's file actions, closed whatever happens.
struct FileActions {
  posix_spawn_file_actions_t actions;
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
};

constexpr const char* kMpiSessionBase = "OMPI_MCA_orte_tmpdir_base";

/// The session directory of one Open MPI program and the environment that names it; the
/// directory and whatever the program left in it go when this does.
class MpiSession {
 public:
  MpiSession() : dir_(make_temp_directory("jam-mpi")) {
    // environ names no session base: the caller made one only then.
    for (char** e = environ; *e; ++e) text_.emplace_back(*e);
    text_.push_back(std::string(kMpiSessionBase) + "=" + dir_.string());
    for (auto& t : text_) env_.push_back(t.data());
    env_.push_back(nullptr);
  }
  ~MpiSession() {
    // A singleton's daemon (orted) outlives the program by a few milliseconds, still removing
    // its own files: try again until it is done, for a second at most (then the directory
    // stays in the temporary directory, which loses nothing).
    for (int attempt = 0; attempt < 100; ++attempt) {
      std::error_code ignored;
      std::filesystem::remove_all(dir_, ignored);
      if (!std::filesystem::exists(dir_, ignored)) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  char** environment() { return env_.data(); }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> text_;
  std::vector<char*> env_;
};

}  // namespace

std::filesystem::path make_temp_directory(const std::string& prefix) {
  std::string name = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(name.data())) {
    throw WriteError(fmt::format("cannot create a directory '{}': {}", name, std::strerror(errno)));
  }
  return name;
}

int run_program(const std::vector<std::string>& argv, const ProcessOptions& o) {
  if (argv.empty()) throw std::runtime_error("run_program: no program given");
  FileActions fa;
  // Output files are opened by the child after its chdir: relative names would then be read
  // against the new directory, so make them absolute first.
  auto absolute = [](const std::string& f) { return std::filesystem::absolute(f).string(); };
  const std::string out = o.stdout_file.empty() ? "" : absolute(o.stdout_file);
  const std::string err = o.stderr_file.empty() ? "" : absolute(o.stderr_file);
  const int flags = O_WRONLY | O_CREAT | O_TRUNC;  // not O_CLOEXEC: they are for the child
  if (!out.empty()) posix_spawn_file_actions_addopen(&fa.actions, 1, out.c_str(), flags, 0644);
  if (!err.empty()) {
    if (err == out) {
      posix_spawn_file_actions_adddup2(&fa.actions, 1, 2);
    } else {
      posix_spawn_file_actions_addopen(&fa.actions, 2, err.c_str(), flags, 0644);
    }
  }
  if (!o.working_directory.empty()) {
    posix_spawn_file_actions_addchdir_np(&fa.actions, o.working_directory.c_str());
  }
  std::vector<char*> args;
  std::vector<std::string> copy = argv;
  for (auto& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  std::optional<MpiSession> session;
  if (o.mpi_program && !std::getenv(kMpiSessionBase)) session.emplace();
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, args[0], &fa.actions, nullptr, args.data(),
                                 session ? session->environment() : environ);
  if (error != 0) {
    throw std::runtime_error(fmt::format("cannot start {}: {}", argv[0], std::strerror(error)));
  }
  int status = 0;
  // Passing a stop on: polled, so that a signal that comes between a look at the flag and a
  // blocking wait is not missed until the child ends by itself.
  bool passed = false;
  for (;;) {
    const pid_t got = waitpid(pid, &status, o.pass_stop_on ? WNOHANG : 0);
    if (got == pid) break;
    if (got < 0 && errno != EINTR)
      throw std::runtime_error(fmt::format("waiting for {} failed", argv[0]));
    if (!o.pass_stop_on) continue;
    if (!passed && stop_was_requested()) {
      ::kill(pid, SIGINT);
      passed = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string find_program(const std::string& name) {
  auto executable = [](const std::string& p) {
    return ::access(p.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(p);
  };
  if (name.find('/') != std::string::npos) return executable(name) ? name : "";
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (executable(candidate)) return candidate;
  }
  return "";
}

}  // namespace jam
