#pragma once
// The least-squares problem behind the scaling fit (scaling_fit.hpp), on a point set that is
// held fixed while the minimiser runs: the model ln p = q ln rate + ln f(x), its residuals and
// analytic Jacobian, the GSL trust-region driver, and the linear sub-problem that gives q and
// the coefficients of ln f for a given phi_J and 1/(z nu).
//
// Parameters: [phi_J, q, 1/(z nu), c_0 .. c_K]. The minimiser works on internal variables for
// q and 1/(z nu), q = 1/(1 + exp(-u)) and 1/(z nu) = exp(v), so that 0 < q < 1 and 1/(z nu) > 0
// hold by construction; the Jacobian carries the chain rule.
#include <cstddef>
#include <vector>

namespace jam::stats::solver {

enum { kPhiJ = 0, kRateExponent = 1, kA = 2, kC0 = 3 };

struct Point {
  std::size_t ensemble, index;
  double phi, ln_rate, ln_p, sigma;  // sigma: standard error of ln p = dp / p
};

struct Problem {
  std::vector<Point> points;
  std::vector<double> full;       // physical parameters (fixed entries stay as they are)
  std::vector<std::size_t> free;  // indices of the free parameters in full
};

struct Solution {
  std::vector<double> par;
  double chi2 = 0.0, rcond = 0.0;
};

double scaling_variable(const std::vector<double>& par, double phi, double ln_rate);

/// ln p of the model at (phi, rate).
double model(const std::vector<double>& par, double phi, double ln_rate);

/// Minimises chi^2 on pr.points from pr.full; throws FitError when it cannot.
Solution solve(const Problem& pr);

/// Sets the free linear parameters of pr.full (q, c_n) by weighted least squares for its
/// phi_J and 1/(z nu); q is then kept inside (0.02, 0.98) as a start.
void linear_start(Problem& pr);

/// Same points (ensemble and index) in the same order.
bool same_points(const std::vector<Point>& a, const std::vector<Point>& b);

}  // namespace jam::stats::solver
