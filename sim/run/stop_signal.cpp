#include "sim/run/stop_signal.hpp"

#include <time.h>
#include <unistd.h>

#include <csignal>
#include <string>

namespace jam {
namespace {
std::atomic<bool> stop_requested{false};
// When the first stop signal came (CLOCK_MONOTONIC, nanoseconds).
std::atomic<long long> first_signal_ns{0};
static_assert(std::atomic<long long>::is_always_lock_free, "read in a signal handler");

/// Signals this close to the first are the same request: a batch system's SIGTERM to every
/// process of a job step arrives with the one its script forwards (Slurm at a time limit),
/// and Ctrl-C reaches jam and the wrapper that forwards it. One second, far below Slurm's
/// KillWait (30 s by default), within which the checkpoint must be written.
constexpr long long kSameRequestNs = 1'000'000'000;

long long monotonic_ns() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);  // async-signal-safe (POSIX)
  return static_cast<long long>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

/// The first SIGINT or SIGTERM asks for a clean stop (a checkpoint, then exit 130); another
/// one more than kSameRequestNs later ends the process at once, as the default action would,
/// for a user or a batch system that will not wait.
extern "C" void jam_request_stop(int) {
  const long long now = monotonic_ns();
  if (!stop_requested.exchange(true)) {
    first_signal_ns.store(now);
    return;
  }
  if (now - first_signal_ns.load() > kSameRequestNs) ::_exit(130);
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
