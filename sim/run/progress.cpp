#include "sim/run/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace jam {

Progress::Progress(bool enabled, double phi_stop)
    : enabled_(enabled && isatty(STDERR_FILENO)),
      phi_stop_(phi_stop),
      start_(Clock::now()),
      last_(start_) {}

void Progress::update(double fraction, double phi, std::size_t steps, std::size_t particles) {
  if (!enabled_) return;
  const auto now = Clock::now();
  if (now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  const std::string bar = std::string(filled, '#') + std::string(kWidth - filled, '.');
  fmt::print(stderr, "\r  phi {:.5f} -> {:.4f} [{}] {:.3g} particle-steps/s  ETA {:.0f} s   ", phi,
             phi_stop_, bar, elapsed > 0 ? steps * static_cast<double>(particles) / elapsed : 0.0,
             eta);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::update_relaxation(double energy, double target, double t) {
  if (!enabled_) return;
  if (first_energy_ < 0.0) first_energy_ = energy;
  const auto now = Clock::now();
  if (now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  // Energy decays roughly exponentially: progress is measured in log(E).
  double fraction = 0.0;
  if (first_energy_ > target && energy > 0.0 && target > 0.0) {
    fraction =
        std::clamp(std::log(first_energy_ / energy) / std::log(first_energy_ / target), 0.0, 1.0);
  }
  fmt::print(stderr,
             "\r  relaxing at zero rate: t {:.0f}, energy/particle {:.2e} -> {:.1e} ({:.0f}%)   ",
             t, energy, target, 100.0 * fraction);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::finish() {
  if (enabled_ && printed_) fmt::print(stderr, "\r{:100}\r", "");
}

}  // namespace jam
