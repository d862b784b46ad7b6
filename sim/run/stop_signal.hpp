#pragma once
// SIGINT and SIGTERM ask a run (or a campaign) to stop cleanly: it writes a checkpoint and
// returns, and the same command resumes it. `jam pipeline` and `--until-decided` ask the same
// flag between their stages and before they publish an output (Interrupted).
#include <atomic>
#include <stdexcept>

namespace jam {

/// Installs the handlers (idempotent) and returns the flag they set.
const std::atomic<bool>& install_stop_handlers();

/// Whether a stop was asked for since the handlers were installed (false when they never were:
/// then a signal ends the process as its default action does).
bool stop_was_requested();

/// Thrown by work that a stop ends before it publishes anything (a stats.h5, checks.json):
/// its caller exits 130, and the outputs are as they were before it began.
struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Throws Interrupted saying `what` was not written when a stop was asked for.
void throw_if_stop_requested(const char* what);

}  // namespace jam
