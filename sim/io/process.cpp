#include "sim/io/process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

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

}  // namespace

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
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, args[0], &fa.actions, nullptr, args.data(), environ);
  if (error != 0) {
    throw std::runtime_error(fmt::format("cannot start {}: {}", argv[0], std::strerror(error)));
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(fmt::format("waiting for {} failed", argv[0]));
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
