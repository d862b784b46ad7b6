#pragma once
// The time left of a campaign, from the planner's estimated particle-steps calibrated by the
// runs already finished. The estimate's scale is the planner's model of steps per unit of
// time; at slow rates near jamming a run takes several times fewer steps than it predicts,
// so dividing the estimate by the measured speed put a 80-minute campaign at "3 days". The
// ratio of real to estimated steps of the finished runs corrects the scale; the relative cost
// of runs, which the estimate gets right, is kept. Both count force evaluations x N (runs
// counted their steps until 2026-11-27, about 17 times fewer than the evaluations planned,
// which put a 14-hour campaign at "18 days" until its first run finished). A campaign
// resumed in a new process starts with the ratio of the runs its earlier processes finished
// (their records).

#include <algorithm>
#include <atomic>
#include <cstdint>

namespace jam {

class ProgressEstimate {
 public:
  /// `remaining`: the estimated particle-steps of the runs this process will do.
  explicit ProgressEstimate(double remaining) : remaining_(remaining) {}

  /// A run finished: its estimate and the particle-steps it took (force evaluations x N,
  /// counted live). A run resumed from a checkpoint (`whole` false) did only the rest of its
  /// estimate: it leaves the work remaining but does not calibrate the scale.
  void finished(double estimated, double real, bool whole = true) {
    estimated_done_.fetch_add(estimated, std::memory_order_relaxed);
    real_done_.fetch_add(real, std::memory_order_relaxed);
    if (!whole) return;
    calibration_estimated_.fetch_add(estimated, std::memory_order_relaxed);
    calibration_real_.fetch_add(real, std::memory_order_relaxed);
  }

  /// Runs finished by earlier processes (before this one starts its runs): their estimate
  /// and the particle-steps their records hold. They calibrate the scale, and are not part
  /// of `remaining`.
  void calibrate(double estimated, double real) {
    earlier_estimated_ += estimated;
    earlier_real_ += real;
  }

  /// Seconds left, given the particle-steps counted live by every run of this process so
  /// far and the seconds they took (0 when nothing has been measured yet).
  double seconds_left(double live_steps, double elapsed) const {
    if (live_steps <= 0 || elapsed <= 0) return 0.0;
    const double estimated = estimated_done_.load(std::memory_order_relaxed);
    const double real = real_done_.load(std::memory_order_relaxed);
    // Before any whole run has finished, in this process or an earlier one: the planner's
    // scale as it is.
    const double cal_estimated =
        calibration_estimated_.load(std::memory_order_relaxed) + earlier_estimated_;
    const double cal_real = calibration_real_.load(std::memory_order_relaxed) + earlier_real_;
    const double ratio = cal_estimated > 0 && cal_real > 0 ? cal_real / cal_estimated : 1.0;
    // The runs under way have done live_steps - real of their share already.
    const double left =
        ratio * std::max(0.0, remaining_ - estimated) - std::max(0.0, live_steps - real);
    return std::max(0.0, left) / (live_steps / elapsed);
  }

 private:
  double remaining_;
  double earlier_estimated_ = 0.0, earlier_real_ = 0.0;       // set before the runs start
  std::atomic<double> estimated_done_{0.0}, real_done_{0.0};  // every run finished here
  std::atomic<double> calibration_estimated_{0.0}, calibration_real_{0.0};  // whole ones
};

}  // namespace jam
