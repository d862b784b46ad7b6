#pragma once
// SIGINT and SIGTERM ask a run (or a campaign) to stop cleanly: it writes a checkpoint and
// returns, and the same command resumes it.
#include <atomic>

namespace jam {

/// Installs the handlers (idempotent) and returns the flag they set.
const std::atomic<bool>& install_stop_handlers();

}  // namespace jam
