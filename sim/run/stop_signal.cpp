#include "sim/run/stop_signal.hpp"

#include <unistd.h>

#include <csignal>
#include <string>

namespace jam {
namespace {
std::atomic<bool> stop_requested{false};

/// The first SIGINT or SIGTERM asks for a clean stop (a checkpoint, then exit 130); a second one
/// ends the process at once, as the default action would, for a user or a batch system that
/// will not wait.
extern "C" void jam_request_stop(int) {
  if (stop_requested.exchange(true)) ::_exit(130);
}
}  // namespace

const std::atomic<bool>& install_stop_handlers() {
  // sigaction without SA_RESTART (std::signal restarts on glibc): a system call that waits,
  // such as an open() of something that never answers, returns EINTR instead of waiting on.
  struct sigaction action {};
  action.sa_handler = jam_request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
  return stop_requested;
}

bool stop_was_requested() {
  return stop_requested.load();
}

void throw_if_stop_requested(const char* what) {
  if (stop_requested.load())
    throw Interrupted(std::string("interrupted: ") + what + " not written");
}

}  // namespace jam
