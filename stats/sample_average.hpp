#pragma once
// Averages over independent samples, accumulate -> finalize -> result, with the error method
// named: the standard error sigma / sqrt(N_s), sigma the sample standard deviation (N_s - 1).
#include <cmath>
#include <cstddef>
#include <limits>

namespace jam::stats {

struct SampleMean {
  double mean = 0.0;
  double error = 0.0;  // standard error of the mean
  std::size_t samples = 0;
  static constexpr const char* kMethod = "standard error over samples, sigma/sqrt(N_s)";
};

class SampleAccumulator {
 public:
  void add(double x) {
    // Welford's update: stable for values with a large common offset.
    ++n_;
    const double delta = x - mean_;
    mean_ += delta / static_cast<double>(n_);
    m2_ += delta * (x - mean_);
  }

  SampleMean finalize() const {
    SampleMean r;
    r.samples = n_;
    r.mean = n_ ? mean_ : std::numeric_limits<double>::quiet_NaN();
    r.error = n_ > 1 ? std::sqrt(m2_ / static_cast<double>(n_ - 1) / static_cast<double>(n_))
                     : std::numeric_limits<double>::quiet_NaN();
    return r;
  }

 private:
  std::size_t n_ = 0;
  double mean_ = 0.0, m2_ = 0.0;
};

}  // namespace jam::stats
