#pragma once
// Covariance of sample means estimated from the samples, and chi^2 with it.
//
// Neighbouring packings of one run are strongly correlated, so a chi^2 with diagonal errors
// is hard to interpret (the paper says so). With S samples and M > S - 1 points the sample
// covariance is singular; it is therefore shrunk towards its diagonal,
//   C = (1 - lambda) C_sample + lambda diag(C_sample),
// with the data-driven lambda of Schaefer & Strimmer (2005, "target D"), which keeps C
// positive definite and reduces to C_sample when the data determine it well.
#include <vector>

namespace jam::stats {

struct ShrunkCovariance {
  std::vector<std::vector<double>> matrix;  // covariance of the mean (divided by S)
  double lambda = 1.0;                      // shrinkage intensity in [0, 1]
};

/// deviations[s][i]: sample s's value at point i minus the mean over samples.
ShrunkCovariance shrunk_covariance_of_mean(const std::vector<std::vector<double>>& deviations);

/// r^T C^-1 r (C from shrunk_covariance_of_mean); throws if C is not positive definite.
double chi2_with_covariance(const std::vector<double>& residual, const ShrunkCovariance& c);

}  // namespace jam::stats
