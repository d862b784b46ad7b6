#include "sim/run/stop_signal.hpp"

#include <csignal>

namespace jam {
namespace {
std::atomic<bool> stop_requested{false};
extern "C" void jam_request_stop(int) {
  stop_requested.store(true);
}
}  // namespace

const std::atomic<bool>& install_stop_handlers() {
  std::signal(SIGINT, jam_request_stop);
  std::signal(SIGTERM, jam_request_stop);
  return stop_requested;
}

}  // namespace jam
