#pragma once
// The critical scaling fit of the paper's Eq. (1):
//   p = rate^q f(x),  x = (phi - phi_J) / rate^(1/(z nu)),  ln f(x) = sum_{n=0..K} c_n x^n,
// fitted to ensemble-averaged pressures by weighted nonlinear least squares in ln p
// (gsl_multifit_nlinear, trust region, analytic Jacobian), on the window
// phi in [phi_min, phi_max], rate <= rate_max, |x| <= x_max at the fitted parameters.
// Derived exponents: beta = (1 - q) z nu, y = q z nu. Errors and bias correction by jackknife
// over samples (each sample left out of every rate at once, the fit repeated on the same
// points), as the paper does. Any of phi_J, q, 1/(z nu) can be held fixed.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/model/paper_values.hpp"
namespace jam::stats {

/// One rate's constant-phi averages: its grid and the per-sample pressures on it.
struct FitEnsemble {
  double rate = 0.0;
  std::vector<double> phi;
  std::vector<std::vector<double>> pressure;  // [sample][point]
  std::vector<std::int64_t> sample_ids;       // sample k shares its start across rates
};

struct ScalingFitOptions {
  int order = 5;  // K, the polynomial order of ln f (the paper's 5)
  double phi_min = 0.0, phi_max = 1.0;
  double rate_max = 1.0;
  double x_max = 1.0;
  std::optional<double> fixed_phi_j, fixed_q, fixed_inv_znu;
  // Starting values (also the centre of a small multi-start); the paper's 2D values.
  double start_phi_j = paper_values(2).phi_j, start_q = paper_values(2).q(),
         start_inv_znu = paper_values(2).inv_znu();
  bool jackknife = true;
};

struct CollapsePoint {
  double rate, phi, x, scaled_pressure, scaled_error;  // p/rate^q and its error
  bool in_fit;
};

struct ScalingFitResult {
  // Jackknife bias-corrected estimates (plain fit values if jackknife is off) and errors.
  double phi_j = 0, q = 0, inv_znu = 0, beta = 0, y = 0;
  double phi_j_err = 0, q_err = 0, inv_znu_err = 0, beta_err = 0, y_err = 0;
  double phi_j_plain = 0, q_plain = 0, inv_znu_plain = 0;
  std::vector<double> coefficients;  // c_0 .. c_K of the plain fit
  std::size_t points = 0, free_parameters = 0, samples = 0;
  double chi2_diag_per_dof = 0;  // diagonal errors (standard errors of the means)
  double chi2_cov_per_dof = 0;   // covariance of the means from the samples, shrunk
  double shrinkage = 0;          // its shrinkage intensity lambda
  double condition_number = 0;   // of the weighted Jacobian at the solution
  std::string fixed;             // which of phi_J, q, 1/(z nu) were held fixed
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
