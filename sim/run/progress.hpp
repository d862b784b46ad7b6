#pragma once
// Progress line on stderr (packing, steps/s, ETA) when stderr is a terminal and the run is
// not quiet; silent otherwise, so CI logs and pipes stay clean.
#include <chrono>
#include <cstddef>

namespace jam {

class Progress {
 public:
  Progress(bool enabled, double phi_stop);
  /// fraction: completed share of the run's time span.
  void update(double fraction, double phi, std::size_t steps, std::size_t particles);
  /// During the zero-rate relaxation: energy per particle against its target.
  void update_relaxation(double energy, double target, double t);
  void finish();
  bool enabled() const { return enabled_; }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  double phi_stop_;
  Clock::time_point start_, last_;
  bool printed_ = false;
  double first_energy_ = -1.0;
};

}  // namespace jam
