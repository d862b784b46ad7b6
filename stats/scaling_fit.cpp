#include "stats/scaling_fit.hpp"

#include <fmt/format.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "stats/covariance.hpp"
#include "stats/jackknife.hpp"

namespace jam::stats {
namespace {

// Full parameter vector: [phi_J, q, 1/(z nu), c_0 .. c_K].
enum { kPhiJ = 0, kQ = 1, kA = 2, kC0 = 3 };

struct Point {
  std::size_t ensemble, index;
  double phi, ln_rate, ln_p, sigma;  // sigma: standard error of ln p = dp / p
};

struct Problem {
  std::vector<Point> points;
  std::vector<double> full;       // current full parameter vector (fixed entries stay)
  std::vector<std::size_t> free;  // indices of the free parameters in full
};

double scaling_variable(const std::vector<double>& par, double phi, double ln_rate) {
  return (phi - par[kPhiJ]) * std::exp(-par[kA] * ln_rate);
}

double model(const std::vector<double>& par, double phi, double ln_rate) {
  const double x = scaling_variable(par, phi, ln_rate);
  double ln_f = 0.0;
  for (std::size_t n = par.size() - 1; n >= kC0; --n) ln_f = ln_f * x + par[n];
  return par[kQ] * ln_rate + ln_f;
}

std::vector<double> expand(const Problem& pr, const gsl_vector* v) {
  std::vector<double> par = pr.full;
  for (std::size_t k = 0; k < pr.free.size(); ++k) par[pr.free[k]] = gsl_vector_get(v, k);
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
  for (std::size_t i = 0; i < pr.points.size(); ++i) {
    const Point& p = pr.points[i];
    const double scale = std::exp(-par[kA] * p.ln_rate);
    const double x = (p.phi - par[kPhiJ]) * scale;
    double dlnf_dx = 0.0;  // d ln f / dx
    for (std::size_t n = order; n >= 1; --n)
      dlnf_dx = dlnf_dx * x + static_cast<double>(n) * par[kC0 + n];
    std::vector<double> d(par.size());
    d[kPhiJ] = -dlnf_dx * scale;
    d[kQ] = p.ln_rate;
    d[kA] = -dlnf_dx * x * p.ln_rate;
    double power = 1.0;
    for (std::size_t n = 0; n <= order; ++n, power *= x) d[kC0 + n] = power;
    for (std::size_t k = 0; k < pr.free.size(); ++k) {
      gsl_matrix_set(j, i, k, -d[pr.free[k]] / p.sigma);  // residual = (data - model)/sigma
    }
  }
  return GSL_SUCCESS;
}

struct Solution {
  std::vector<double> par;
  double chi2 = 0.0, rcond = 0.0;
};

Solution solve(Problem& pr) {
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
  for (std::size_t k = 0; k < p; ++k) gsl_vector_set(x0, k, pr.full[pr.free[k]]);
  gsl_multifit_nlinear_init(x0, &fdf, w);
  int info = 0;
  const int status =
      gsl_multifit_nlinear_driver(500, 1e-12, 1e-12, 1e-12, nullptr, nullptr, &info, w);
  Solution s;
  s.par = expand(pr, gsl_multifit_nlinear_position(w));
  gsl_blas_ddot(gsl_multifit_nlinear_residual(w), gsl_multifit_nlinear_residual(w), &s.chi2);
  gsl_multifit_nlinear_rcond(&s.rcond, w);
  gsl_vector_free(x0);
  gsl_multifit_nlinear_free(w);
  if (status != GSL_SUCCESS || !std::isfinite(s.chi2)) {
    throw FitError(fmt::format("fit did not converge: {}", gsl_strerror(status)));
  }
  return s;
}

// Linear start: for given phi_J and 1/(z nu), ln p - q ln rate = sum c_n x^n is linear in
// (q, c_n); solve it by weighted least squares.
void linear_start(Problem& pr) {
  std::vector<std::size_t> linear;
  for (std::size_t k : pr.free)
    if (k == kQ || k >= kC0) linear.push_back(k);
  const auto n = static_cast<Eigen::Index>(pr.points.size());
  Eigen::MatrixXd a(n, static_cast<Eigen::Index>(linear.size()));
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Point& p = pr.points[static_cast<std::size_t>(i)];
    const double x = scaling_variable(pr.full, p.phi, p.ln_rate);
    double rhs = p.ln_p;
    if (std::find(linear.begin(), linear.end(), std::size_t{kQ}) == linear.end())
      rhs -= pr.full[kQ] * p.ln_rate;
    for (std::size_t c = 0; c < linear.size(); ++c) {
      const std::size_t k = linear[c];
      a(i, static_cast<Eigen::Index>(c)) =
          (k == kQ ? p.ln_rate : std::pow(x, static_cast<double>(k - kC0))) / p.sigma;
    }
    b(i) = rhs / p.sigma;
  }
  const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(b);
  for (std::size_t c = 0; c < linear.size(); ++c)
    pr.full[linear[c]] = sol(static_cast<Eigen::Index>(c));
}

struct Means {
  std::vector<std::vector<double>> mean, error;  // [ensemble][point]
};

Means ensemble_means(const std::vector<FitEnsemble>& ens, std::int64_t excluded_id) {
  Means m;
  for (const auto& e : ens) {
    std::vector<double> mean(e.phi.size(), 0.0), m2(e.phi.size(), 0.0);
    std::size_t used = 0;
    for (std::size_t s = 0; s < e.pressure.size(); ++s) {
      if (e.sample_ids[s] == excluded_id) continue;
      ++used;
      for (std::size_t k = 0; k < e.phi.size(); ++k) {
        const double d = e.pressure[s][k] - mean[k];
        mean[k] += d / static_cast<double>(used);
        m2[k] += d * (e.pressure[s][k] - mean[k]);
      }
    }
    std::vector<double> err(e.phi.size());
    for (std::size_t k = 0; k < e.phi.size(); ++k) {
      err[k] = used > 1
                   ? std::sqrt(m2[k] / static_cast<double>(used - 1) / static_cast<double>(used))
                   : std::numeric_limits<double>::quiet_NaN();
    }
    m.mean.push_back(std::move(mean));
    m.error.push_back(std::move(err));
  }
  return m;
}

// Candidate points: inside the phi window and below rate_max, with a usable mean.
std::vector<Point> candidates(const std::vector<FitEnsemble>& ens, const Means& m,
                              const ScalingFitOptions& o) {
  std::vector<Point> pts;
  for (std::size_t e = 0; e < ens.size(); ++e) {
    if (ens[e].rate > o.rate_max * (1 + 1e-9)) continue;
    for (std::size_t k = 0; k < ens[e].phi.size(); ++k) {
      const double phi = ens[e].phi[k], p = m.mean[e][k], dp = m.error[e][k];
      if (phi < o.phi_min || phi > o.phi_max || !(p > 0) || !(dp > 0)) continue;
      pts.push_back({e, k, phi, std::log(ens[e].rate), std::log(p), dp / p});
    }
  }
  return pts;
}

std::vector<Point> in_window(const std::vector<Point>& all, const std::vector<double>& par,
                             double x_max) {
  std::vector<Point> pts;
  for (const Point& p : all)
    if (std::abs(scaling_variable(par, p.phi, p.ln_rate)) <= x_max) pts.push_back(p);
  return pts;
}

// Fit with the |x| <= x_max window re-selected at the current parameters until it is stable.
Solution fit_with_window(const std::vector<Point>& all, std::vector<double> start,
                         const std::vector<std::size_t>& free, double x_max,
                         std::vector<Point>& used) {
  Problem pr{in_window(all, start, x_max), start, free};
  linear_start(pr);
  Solution s;
  for (int iteration = 0; iteration < 20; ++iteration) {
    s = solve(pr);
    std::vector<Point> next = in_window(all, s.par, x_max);
    const bool same =
        next.size() == pr.points.size() &&
        std::equal(next.begin(), next.end(), pr.points.begin(), [](const Point& a, const Point& b) {
          return a.ensemble == b.ensemble && a.index == b.index;
        });
    if (same) break;
    pr.points = std::move(next);
    pr.full = s.par;
  }
  used = pr.points;
  return s;
}

}  // namespace

ScalingFitResult fit_scaling(const std::vector<FitEnsemble>& ens, const ScalingFitOptions& o) {
  if (o.order < 0 || o.order > 9)
    throw FitError(fmt::format("fit: polynomial order {} (0..9)", o.order));
  gsl_set_error_handler_off();
  const Means full_means = ensemble_means(ens, std::numeric_limits<std::int64_t>::min());
  const std::vector<Point> all = candidates(ens, full_means, o);
  if (all.empty()) {
    throw FitError(fmt::format("fit: no data in the window phi in [{:g}, {:g}], rate <= {:g}",
                               o.phi_min, o.phi_max, o.rate_max));
  }
  std::vector<double> start(kC0 + static_cast<std::size_t>(o.order) + 1, 0.0);
  start[kPhiJ] = o.fixed_phi_j.value_or(o.start_phi_j);
  start[kQ] = o.fixed_q.value_or(o.start_q);
  start[kA] = o.fixed_inv_znu.value_or(o.start_inv_znu);
  std::vector<std::size_t> free;
  std::vector<std::string> fixed;
  if (!o.fixed_phi_j)
    free.push_back(kPhiJ);
  else
    fixed.push_back("phi_J");
  if (!o.fixed_q)
    free.push_back(kQ);
  else
    fixed.push_back("q");
  if (!o.fixed_inv_znu)
    free.push_back(kA);
  else
    fixed.push_back("1/(z nu)");
  for (std::size_t k = kC0; k < start.size(); ++k) free.push_back(k);

  // Multi-start around the starting values; the best converged fit wins.
  std::vector<double> phi_starts = {start[kPhiJ]}, a_starts = {start[kA]};
  if (!o.fixed_phi_j)
    phi_starts = {start[kPhiJ], start[kPhiJ] - 0.005, start[kPhiJ] + 0.005, start[kPhiJ] - 0.01,
                  start[kPhiJ] + 0.01};
  if (!o.fixed_inv_znu) a_starts = {start[kA], 0.8 * start[kA], 1.25 * start[kA]};
  Solution best;
  std::vector<Point> best_points;
  double best_score = std::numeric_limits<double>::infinity();
  std::string last_error = "no start converged";
  for (double phi0 : phi_starts) {
    for (double a0 : a_starts) {
      std::vector<double> s0 = start;
      s0[kPhiJ] = phi0;
      s0[kA] = a0;
      try {
        std::vector<Point> used;
        const Solution s = fit_with_window(all, s0, free, o.x_max, used);
        const double score = s.chi2 / static_cast<double>(used.size() - free.size());
        if (score < best_score) {
          best_score = score;
          best = s;
          best_points = used;
        }
      } catch (const FitError& e) {
        last_error = e.what();
      }
    }
  }
  if (!std::isfinite(best_score)) throw FitError(last_error);

  ScalingFitResult r;
  r.points = best_points.size();
  r.free_parameters = free.size();
  const double dof = static_cast<double>(r.points - r.free_parameters);
  r.chi2_diag_per_dof = best.chi2 / dof;
  r.condition_number = best.rcond > 0 ? 1.0 / best.rcond : std::numeric_limits<double>::infinity();
  r.coefficients.assign(best.par.begin() + kC0, best.par.end());
  for (std::size_t k = 0; k < fixed.size(); ++k) r.fixed += (k ? ", " : "") + fixed[k];
  r.phi_j_plain = best.par[kPhiJ];
  r.q_plain = best.par[kQ];
  r.inv_znu_plain = best.par[kA];

  // Sample ids (a sample is left out of every rate at once) and chi^2 with the covariance.
  std::set<std::int64_t> ids;
  for (const auto& e : ens)
    for (auto id : e.sample_ids) ids.insert(id);
  r.samples = ids.size();
  {
    std::vector<std::vector<double>> deviations;
    for (auto id : ids) {
      std::vector<double> row;
      for (const Point& p : best_points) {
        const auto& e = ens[p.ensemble];
        const auto it = std::find(e.sample_ids.begin(), e.sample_ids.end(), id);
        const double mean = full_means.mean[p.ensemble][p.index];
        row.push_back(
            it == e.sample_ids.end()
                ? 0.0
                : (e.pressure[static_cast<std::size_t>(it - e.sample_ids.begin())][p.index] -
                   mean) /
                      mean);
      }
      deviations.push_back(std::move(row));
    }
    std::vector<double> residual;
    for (const Point& p : best_points)
      residual.push_back(p.ln_p - model(best.par, p.phi, p.ln_rate));
    // With fewer than 3 samples a covariance cannot be estimated at all; if the shrunk
    // estimate is still singular the chi^2 is reported as not available (NaN).
    r.chi2_cov_per_dof = std::numeric_limits<double>::quiet_NaN();
    r.shrinkage = std::numeric_limits<double>::quiet_NaN();
    if (deviations.size() >= 3) {
      const ShrunkCovariance c = shrunk_covariance_of_mean(deviations);
      r.shrinkage = c.lambda;
      try {
        r.chi2_cov_per_dof = chi2_with_covariance(residual, c) / dof;
      } catch (const std::runtime_error&) {
      }
    }
  }

  auto derived = [](const std::vector<double>& par) {
    return std::vector<double>{par[kPhiJ], par[kQ], par[kA], (1.0 - par[kQ]) / par[kA],
                               par[kQ] / par[kA]};
  };
  std::vector<double> est = derived(best.par), err(5, 0.0);
  if (o.jackknife && ids.size() >= 2) {
    const std::vector<std::int64_t> id_list(ids.begin(), ids.end());
    std::vector<std::vector<double>> replicas;
    for (auto id : id_list) {
      const Means m = ensemble_means(ens, id);
      Problem pr{best_points, best.par, free};
      for (Point& p : pr.points) p.ln_p = std::log(m.mean[p.ensemble][p.index]);  // same weights
      replicas.push_back(derived(solve(pr).par));
    }
    const JackknifeResult j = jackknife(id_list.size(), [&](std::size_t k) {
      return k == id_list.size() ? derived(best.par) : replicas[k];
    });
    est = j.estimate;
    err = j.error;
    r.error_method = JackknifeResult::kMethod;
  } else {
    r.error_method = "none (jackknife off or fewer than 2 samples)";
  }
  // Held parameters are exact, and so are the exponents they determine.
  if (o.fixed_phi_j) est[0] = *o.fixed_phi_j, err[0] = 0.0;
  if (o.fixed_q) est[1] = *o.fixed_q, err[1] = 0.0;
  if (o.fixed_inv_znu) est[2] = *o.fixed_inv_znu, err[2] = 0.0;
  if (o.fixed_q && o.fixed_inv_znu) {
    est[3] = (1.0 - est[1]) / est[2], err[3] = 0.0;
    est[4] = est[1] / est[2], err[4] = 0.0;
  }
  r.phi_j = est[0];
  r.q = est[1];
  r.inv_znu = est[2];
  r.beta = est[3];
  r.y = est[4];
  r.phi_j_err = err[0];
  r.q_err = err[1];
  r.inv_znu_err = err[2];
  r.beta_err = err[3];
  r.y_err = err[4];

  // The collapse, for every point of every rate, with the plain fit's parameters.
  std::set<std::pair<std::size_t, std::size_t>> used;
  for (const Point& p : best_points) used.insert({p.ensemble, p.index});
  for (std::size_t e = 0; e < ens.size(); ++e) {
    for (std::size_t k = 0; k < ens[e].phi.size(); ++k) {
      const double p = full_means.mean[e][k], dp = full_means.error[e][k];
      if (!(p > 0)) continue;
      const double ln_rate = std::log(ens[e].rate);
      const double scale = std::exp(-best.par[kQ] * ln_rate);
      r.collapse.push_back({ens[e].rate, ens[e].phi[k],
                            scaling_variable(best.par, ens[e].phi[k], ln_rate), p * scale,
                            dp * scale, used.count({e, k}) > 0});
    }
  }
  return r;
}

}  // namespace jam::stats
