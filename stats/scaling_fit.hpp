#pragma once
// The critical scaling fit of the paper's Eq. (1):
//   p = rate^q f(x),  x = (phi - phi_J) / rate^(1/(z nu)),  ln f(x) = sum_{n=0..K} c_n x^n,
// fitted to ensemble-averaged pressures by weighted nonlinear least squares in ln p
// (gsl_multifit_nlinear, trust region, analytic Jacobian), on the window
// phi in phi_J +- half_window, rate <= rate_max, |x| <= x_max. Nothing depends on the paper's
// values: the start comes from the data (where d ln p / d ln rate crosses 1/2: the crossover
// from p ~ rate below jamming to a rate-independent p above it), the window is centred on the
// fitted phi_J by an outer iteration to a fixed point, and the point set is chosen from the
// current estimate and held fixed while the minimiser runs (re-choosing it is the outer
// iteration; starts are compared only on the same point set). 1/(z nu) > 0 and 0 < q < 1 by
// parametrisation (exp, logistic); a fit that ends on a bound is a failure, not a result.
// Derived exponents: beta = (1 - q) z nu, y = q z nu. Errors and bias correction by jackknife
// over samples (each sample left out of every rate at once, the fit repeated on the same
// points), as the paper does. Any of phi_J, q, 1/(z nu) can be held fixed.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace jam::stats {

/// One rate's constant-phi averages: its grid and the per-sample pressures on it.
struct FitEnsemble {
  double rate = 0.0;
  std::vector<double> phi;
  std::vector<std::vector<double>> pressure;  // [sample][point]
  std::vector<std::int64_t> sample_ids;       // sample k shares its start across rates
};

struct ScalingFitOptions {
  int order = 5;              // K, the polynomial order of ln f (the paper's 5)
  double half_window = 0.01;  // phi window: the fitted phi_J +- this (an outer iteration)
  double rate_max = 1.0;
  double x_max = 1.0;
  std::optional<double> fixed_phi_j, fixed_rate_exponent, fixed_inv_znu;
  bool jackknife = true;
  int max_iterations = 30;  // of the window's re-centring
  double tolerance = 1e-4;  // the window has settled when phi_J moves less than this
};

struct CollapsePoint {
  double rate, phi, x, scaled_pressure, scaled_error;  // p/rate^q and its error
  bool in_fit;
};

/// Thresholds of the quality flag (docs/statistics-and-checks.md says why).
constexpr double kChi2DisagreementFactor = 10.0;  // chi^2 with the covariance vs diagonal
constexpr double kIllConditioned = 1e10;          // condition number of the weighted Jacobian
constexpr std::size_t kMinPointsPerRate = 5;      // points of every fitted rate in the window
// Absolute: chi^2/dof (with the covariance, else diagonal) above this, the form does not
// describe the data. The stored paper-2d scan's good rows lie at 0.35-1.3 and its +-0.03 rows,
// a spurious fixed point of the window iteration, at 116-203 (docs/reproduction.md).
constexpr double kMaxChi2PerDof = 3.0;
// Informative: a fit whose jackknife error of beta or y exceeds half the value cannot tell an
// exponent from its half or double. Such fits agree with anything within their errors, so they
// would make any scan look flat (reduced-2d's slowest row: beta 1.2 +- 3.5 while the scan
// drifts from 1.8 to 3.5); they are kept in the scan, flagged poor.
constexpr double kMaxRelativeError = 0.5;

struct ScalingFitResult {
  // Jackknife bias-corrected estimates (plain fit values if jackknife is off) and errors.
  // rate_exponent is Eq. 1's q (not the quality factor Q of inertial runs).
  double phi_j = 0, rate_exponent = 0, inv_znu = 0, beta = 0, y = 0;
  double phi_j_err = 0, rate_exponent_err = 0, inv_znu_err = 0, beta_err = 0, y_err = 0;
  // The plain fit to all samples.
  double phi_j_plain = 0, rate_exponent_plain = 0, inv_znu_plain = 0, beta_plain = 0, y_plain = 0;
  std::vector<double> coefficients;  // c_0 .. c_K of the plain fit
  std::size_t points = 0, free_parameters = 0, samples = 0;
  std::size_t min_points_per_rate = 0;  // the fewest points of any fitted rate in the window
  double phi_min = 0, phi_max = 0;      // the window the fit settled on
  int iterations = 0;                   // re-centrings of the window until it settled
  std::string start;                    // where the minimiser started, and why
  double chi2_diag_per_dof = 0;         // diagonal errors (standard errors of the means)
  double chi2_cov_per_dof = 0;          // covariance of the means from the samples, shrunk
  double shrinkage = 0;                 // its shrinkage intensity lambda
  double condition_number = 0;          // of the weighted Jacobian at the solution
  std::string quality = "ok";           // "ok" or "poor"
  std::string quality_reason;           // why poor
  std::string fixed;                    // which of phi_J, q, 1/(z nu) were held fixed
  std::string error_method;
  std::vector<CollapsePoint> collapse;
};

/// A fit that cannot be done (no data in the window, too few points, no convergence).
struct FitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

ScalingFitResult fit_scaling(const std::vector<FitEnsemble>& ensembles,
                             const ScalingFitOptions& options);

}  // namespace jam::stats
