#pragma once
// Jackknife over samples (leave one sample out), the error method of the paper: for any
// function f of sample averages, with S samples and f_(i) the value without sample i,
//   estimate  f_J  = S f(all) - (S - 1) mean_i f_(i)              (bias-corrected)
//   error     dF   = sqrt((S - 1)/S * sum_i (f_(i) - mean_i f_(i))^2).
// Samples are the independent unit: points along one compression run are correlated, so a
// sample is always a whole run (or a whole set of runs sharing a start), never a point.
#include <cmath>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <vector>

namespace jam::stats {

struct JackknifeResult {
  std::vector<double> estimate;  // bias-corrected
  std::vector<double> error;
  std::vector<double> plain;  // f(all samples), not corrected
  static constexpr const char* kMethod = "jackknife over samples (leave one out)";
};

/// value(excluded) returns f computed without sample `excluded`, or with all samples when
/// excluded == samples. Every call must return vectors of the same length.
inline JackknifeResult jackknife(std::size_t samples,
                                 const std::function<std::vector<double>(std::size_t)>& value) {
  if (samples < 2) throw std::invalid_argument("jackknife: needs at least 2 samples");
  JackknifeResult r;
  r.plain = value(samples);
  const std::size_t m = r.plain.size();
  std::vector<std::vector<double>> leave_out(samples);
  std::vector<double> mean(m, 0.0);
  for (std::size_t i = 0; i < samples; ++i) {
    leave_out[i] = value(i);
    if (leave_out[i].size() != m) throw std::invalid_argument("jackknife: inconsistent sizes");
    for (std::size_t k = 0; k < m; ++k) mean[k] += leave_out[i][k] / static_cast<double>(samples);
  }
  const double s = static_cast<double>(samples);
  r.estimate.resize(m);
  r.error.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    double sum2 = 0.0;
    for (std::size_t i = 0; i < samples; ++i)
      sum2 += (leave_out[i][k] - mean[k]) * (leave_out[i][k] - mean[k]);
    r.estimate[k] = s * r.plain[k] - (s - 1.0) * mean[k];
    r.error[k] = std::sqrt((s - 1.0) / s * sum2);
  }
  return r;
}

/// Mean over samples of column k of a samples x points table, leaving out sample `excluded`
/// (none when excluded >= rows).
inline std::vector<double> column_means(const std::vector<std::vector<double>>& table,
                                        std::size_t excluded) {
  if (table.empty()) return {};
  std::vector<double> mean(table.front().size(), 0.0);
  std::size_t used = 0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (i == excluded) continue;
    ++used;
    for (std::size_t k = 0; k < mean.size(); ++k) mean[k] += table[i][k];
  }
  for (double& x : mean) x /= static_cast<double>(used);
  return mean;
}

}  // namespace jam::stats
