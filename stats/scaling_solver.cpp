#include "stats/scaling_solver.hpp"

#include <fmt/format.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "stats/scaling_fit.hpp"

namespace jam::stats::solver {
namespace {

// Internal variables of the bounded parameters, and back.
double to_internal(std::size_t k, double value) {
  if (k == kRateExponent) return std::log(value / (1.0 - value));
  if (k == kA) return std::log(value);
  return value;
}

double to_physical(std::size_t k, double u) {
  if (k == kRateExponent) return 1.0 / (1.0 + std::exp(-u));
  if (k == kA) return std::exp(u);
  return u;
}

std::vector<double> expand(const Problem& pr, const gsl_vector* v) {
  std::vector<double> par = pr.full;
  for (std::size_t k = 0; k < pr.free.size(); ++k) {
    par[pr.free[k]] = to_physical(pr.free[k], gsl_vector_get(v, k));
  }
  return par;
}

int residuals(const gsl_vector* v, void* data, gsl_vector* f) {
  const auto& pr = *static_cast<const Problem*>(data);
  const auto par = expand(pr, v);
  for (std::size_t i = 0; i < pr.points.size(); ++i) {
    const Point& p = pr.points[i];
    gsl_vector_set(f, i, (p.ln_p - model(par, p.phi, p.ln_rate)) / p.sigma);
  }
  return GSL_SUCCESS;
}

int jacobian(const gsl_vector* v, void* data, gsl_matrix* j) {
  const auto& pr = *static_cast<const Problem*>(data);
  const auto par = expand(pr, v);
  const std::size_t order = par.size() - kC0 - 1;
  // d(physical)/d(internal): q (1 - q) for the logistic, 1/(z nu) for the exponential.
  const double dq = par[kRateExponent] * (1.0 - par[kRateExponent]), da = par[kA];
  std::vector<double> d(par.size());
  for (std::size_t i = 0; i < pr.points.size(); ++i) {
    const Point& p = pr.points[i];
    const double scale = std::exp(-par[kA] * p.ln_rate);
    const double x = (p.phi - par[kPhiJ]) * scale;
    double dlnf_dx = 0.0;
    for (std::size_t n = order; n >= 1; --n)
      dlnf_dx = dlnf_dx * x + static_cast<double>(n) * par[kC0 + n];
    d[kPhiJ] = -dlnf_dx * scale;
    d[kRateExponent] = p.ln_rate * dq;
    d[kA] = -dlnf_dx * x * p.ln_rate * da;
    double power = 1.0;
    for (std::size_t n = 0; n <= order; ++n, power *= x) d[kC0 + n] = power;
    for (std::size_t k = 0; k < pr.free.size(); ++k) {
      gsl_matrix_set(j, i, k, -d[pr.free[k]] / p.sigma);  // residual = (data - model)/sigma
    }
  }
  return GSL_SUCCESS;
}

}  // namespace

double scaling_variable(const std::vector<double>& par, double phi, double ln_rate) {
  return (phi - par[kPhiJ]) * std::exp(-par[kA] * ln_rate);
}

double model(const std::vector<double>& par, double phi, double ln_rate) {
  const double x = scaling_variable(par, phi, ln_rate);
  double ln_f = 0.0;
  for (std::size_t n = par.size() - 1; n >= kC0; --n) ln_f = ln_f * x + par[n];
  return par[kRateExponent] * ln_rate + ln_f;
}

Solution solve(const Problem& pr_in) {
  Problem pr = pr_in;
  const std::size_t n = pr.points.size(), p = pr.free.size();
  if (n <= p) {
    throw FitError(fmt::format("fit: {} points in the window for {} free parameters", n, p));
  }
  gsl_multifit_nlinear_fdf fdf{};
  fdf.f = residuals;
  fdf.df = jacobian;
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = p;
  fdf.params = &pr;
  gsl_multifit_nlinear_parameters params = gsl_multifit_nlinear_default_parameters();
  gsl_multifit_nlinear_workspace* w =
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &params, n, p);
  gsl_vector* x0 = gsl_vector_alloc(p);
  for (std::size_t k = 0; k < p; ++k) {
    gsl_vector_set(x0, k, to_internal(pr.free[k], pr.full[pr.free[k]]));
  }
  gsl_multifit_nlinear_init(x0, &fdf, w);
  int info = 0;
  int status = gsl_multifit_nlinear_driver(2000, 1e-10, 1e-10, 1e-12, nullptr, nullptr, &info, w);
  // A minimum along a very flat direction can crawl past the iteration limit with the step
  // and gradient tests still failing by a hair: accept it when the looser tests (relative step
  // 1e-8, scaled gradient 1e-6) hold there.
  if (status == GSL_EMAXITER &&
      gsl_multifit_nlinear_test(1e-8, 1e-6, 0.0, &info, w) == GSL_SUCCESS && info != 0) {
    status = GSL_SUCCESS;
  }
  Solution s;
  s.par = expand(pr, gsl_multifit_nlinear_position(w));
  gsl_blas_ddot(gsl_multifit_nlinear_residual(w), gsl_multifit_nlinear_residual(w), &s.chi2);
  gsl_multifit_nlinear_rcond(&s.rcond, w);
  gsl_vector_free(x0);
  gsl_multifit_nlinear_free(w);
  if (status != GSL_SUCCESS || !std::isfinite(s.chi2)) {
    throw FitError(
        fmt::format("fit did not converge: {} (at phi_J {:.5g}, q {:.4g}, 1/(z nu) {:.4g})",
                    gsl_strerror(status), s.par[kPhiJ], s.par[kRateExponent], s.par[kA]));
  }
  return s;
}

void linear_start(Problem& pr) {
  std::vector<std::size_t> linear;
  for (std::size_t k : pr.free)
    if (k == kRateExponent || k >= kC0) linear.push_back(k);
  const bool rate_exponent_free =
      std::find(linear.begin(), linear.end(), std::size_t{kRateExponent}) != linear.end();
  const auto n = static_cast<Eigen::Index>(pr.points.size());
  Eigen::MatrixXd a(n, static_cast<Eigen::Index>(linear.size()));
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Point& p = pr.points[static_cast<std::size_t>(i)];
    const double x = scaling_variable(pr.full, p.phi, p.ln_rate);
    const double rhs = rate_exponent_free ? p.ln_p : p.ln_p - pr.full[kRateExponent] * p.ln_rate;
    for (std::size_t c = 0; c < linear.size(); ++c) {
      const std::size_t k = linear[c];
      a(i, static_cast<Eigen::Index>(c)) =
          (k == kRateExponent ? p.ln_rate : std::pow(x, static_cast<double>(k - kC0))) / p.sigma;
    }
    b(i) = rhs / p.sigma;
  }
  const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
  for (std::size_t c = 0; c < linear.size(); ++c)
    pr.full[linear[c]] = sol(static_cast<Eigen::Index>(c));
  if (rate_exponent_free)
    pr.full[kRateExponent] = std::isfinite(pr.full[kRateExponent])
                                 ? std::clamp(pr.full[kRateExponent], 0.02, 0.98)
                                 : 0.5;
}

bool same_points(const std::vector<Point>& a, const std::vector<Point>& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](const Point& x, const Point& y) {
           return x.ensemble == y.ensemble && x.index == y.index;
         });
}

}  // namespace jam::stats::solver
