#include "stats/covariance.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jam::stats {

ShrunkCovariance shrunk_covariance_of_mean(const std::vector<std::vector<double>>& deviations) {
  const std::size_t s = deviations.size();
  if (s < 2) throw std::invalid_argument("covariance: needs at least 2 samples");
  const std::size_t m = deviations.front().size();
  Eigen::MatrixXd x(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(m));
  for (std::size_t a = 0; a < s; ++a)
    for (std::size_t i = 0; i < m; ++i)
      x(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(i)) = deviations[a][i];
  const double n = static_cast<double>(s);
  const Eigen::MatrixXd sample = x.transpose() * x / (n - 1.0);
  // Standardised data for the shrinkage intensity (Schaefer & Strimmer, target D).
  Eigen::VectorXd sd = sample.diagonal().cwiseSqrt();
  for (Eigen::Index i = 0; i < sd.size(); ++i)
    if (sd(i) <= 0) sd(i) = 1.0;
  const Eigen::MatrixXd z = x * sd.cwiseInverse().asDiagonal();
  double numerator = 0.0, denominator = 0.0;
  for (Eigen::Index i = 0; i < z.cols(); ++i) {
    for (Eigen::Index j = 0; j < z.cols(); ++j) {
      if (i == j) continue;
      const Eigen::VectorXd w = z.col(i).cwiseProduct(z.col(j));
      const double mean_w = w.mean();
      const double r = mean_w * n / (n - 1.0);
      const double var_r = n / std::pow(n - 1.0, 3) * (w.array() - mean_w).square().sum();
      numerator += var_r;
      denominator += r * r;
    }
  }
  ShrunkCovariance c;
  c.lambda = denominator > 0 ? std::clamp(numerator / denominator, 0.0, 1.0) : 1.0;
  c.matrix.assign(m, std::vector<double>(m, 0.0));
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j < m; ++j) {
      const double v = sample(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      c.matrix[i][j] = (i == j ? v : (1.0 - c.lambda) * v) / n;
    }
  }
  return c;
}

double chi2_with_covariance(const std::vector<double>& residual, const ShrunkCovariance& c) {
  const auto m = static_cast<Eigen::Index>(residual.size());
  Eigen::MatrixXd cov(m, m);
  Eigen::VectorXd r(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    r(i) = residual[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < m; ++j)
      cov(i, j) = c.matrix[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(cov);
  if (llt.info() != Eigen::Success) throw std::runtime_error("covariance is not positive definite");
  return r.dot(llt.solve(r));
}

}  // namespace jam::stats
