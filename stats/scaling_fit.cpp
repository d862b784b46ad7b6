#include "stats/scaling_fit.hpp"

#include <fmt/format.h>
#include <gsl/gsl_errno.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "stats/covariance.hpp"
#include "stats/jackknife.hpp"
#include "stats/scaling_solver.hpp"

namespace jam::stats {
namespace {

using namespace solver;

// Where a bounded parameter counts as having run onto its bound: q within this of 0 or 1,
// 1/(z nu) below it or above its inverse.
constexpr double kBound = 1e-3;

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

bool fitted_rate(const FitEnsemble& e, const ScalingFitOptions& o) {
  return e.rate <= o.rate_max * (1 + 1e-9);
}

// Candidate points: phi within centre +- half_window, rate <= rate_max, a usable mean.
std::vector<Point> candidates(const std::vector<FitEnsemble>& ens, const Means& m,
                              const ScalingFitOptions& o, double centre) {
  std::vector<Point> pts;
  for (std::size_t e = 0; e < ens.size(); ++e) {
    if (!fitted_rate(ens[e], o)) continue;
    for (std::size_t k = 0; k < ens[e].phi.size(); ++k) {
      const double phi = ens[e].phi[k], p = m.mean[e][k], dp = m.error[e][k];
      if (std::abs(phi - centre) > o.half_window + 1e-12 || !(p > 0) || !(dp > 0)) continue;
      pts.push_back({e, k, phi, std::log(ens[e].rate), std::log(p), dp / p});
    }
  }
  return pts;
}

// The point set at parameters par: the candidates around par's phi_J with |x| <= x_max.
std::vector<Point> point_set(const std::vector<FitEnsemble>& ens, const Means& m,
                             const ScalingFitOptions& o, const std::vector<double>& par) {
  std::vector<Point> pts;
  for (const Point& p : candidates(ens, m, o, par[kPhiJ])) {
    if (std::abs(scaling_variable(par, p.phi, p.ln_rate)) <= o.x_max) pts.push_back(p);
  }
  return pts;
}

/// A phi_J outside the packings every fitted rate compressed through is not a jamming point
/// of these data (an extrapolation the window's polynomial cannot support): refused.
void refuse_outside_compressed_range(const std::vector<FitEnsemble>& ens,
                                     const ScalingFitOptions& o, double phi_j) {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  for (const auto& e : ens) {
    if (!fitted_rate(e, o) || e.phi.empty()) continue;
    lo = std::max(lo, e.phi.front());
    hi = std::min(hi, e.phi.back());
  }
  if (!(phi_j > lo && phi_j < hi)) {
    throw FitError(fmt::format(
        "fit: phi_J = {:.6g} lies outside the packings every fitted rate compressed through "
        "[{:.6g}, {:.6g}]",
        phi_j, lo, hi));
  }
}

/// ln <p> of ensemble e at phi, linear in phi between grid points; NaN outside its data.
double ln_mean_at(const FitEnsemble& e, const std::vector<double>& mean, double phi) {
  const auto it = std::lower_bound(e.phi.begin(), e.phi.end(), phi - 1e-12);
  if (it == e.phi.end()) return NAN;
  const auto k = static_cast<std::size_t>(it - e.phi.begin());
  if (std::abs(e.phi[k] - phi) <= 1e-12) return mean[k] > 0 ? std::log(mean[k]) : NAN;
  if (k == 0 || !(mean[k] > 0) || !(mean[k - 1] > 0)) return NAN;
  const double t = (phi - e.phi[k - 1]) / (e.phi[k] - e.phi[k - 1]);
  return (1 - t) * std::log(mean[k - 1]) + t * std::log(mean[k]);
}

/// The start of phi_J from the data alone: q_eff(phi) = d ln<p>/d ln rate, fitted across the
/// rates at each packing of the slowest rate's grid, is about 1 below jamming (p ~ rate) and
/// about 0 above it (p independent of the rate); phi_J0 is where it last crosses 1/2 going
/// down. Returns phi_J0 and the words for the result.
std::pair<double, std::string> crossover(const std::vector<FitEnsemble>& ens, const Means& m,
                                         const ScalingFitOptions& o) {
  std::vector<std::size_t> rates;
  for (std::size_t e = 0; e < ens.size(); ++e)
    if (fitted_rate(ens[e], o)) rates.push_back(e);
  // Two rates leave phi_J and q trading off against each other (a fit on two rates once
  // returned phi_J = 0.596, below the runs' phi_init): three at least.
  if (rates.size() < 3) {
    throw FitError(fmt::format(
        "fit: {} rate(s) at or below rate_max {:g}; a scaling fit needs at least 3 (with 2, "
        "phi_J and q trade off)",
        rates.size(), o.rate_max));
  }
  const std::size_t slowest = *std::min_element(
      rates.begin(), rates.end(), [&](auto a, auto b) { return ens[a].rate < ens[b].rate; });
  std::vector<double> phi, slope;
  for (double x : ens[slowest].phi) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (auto e : rates) {
      const double y = ln_mean_at(ens[e], m.mean[e], x), lr = std::log(ens[e].rate);
      if (!std::isfinite(y)) break;
      sx += lr, sy += y, sxx += lr * lr, sxy += lr * y, n += 1;
    }
    if (n < static_cast<double>(rates.size())) continue;  // a rate without data here
    phi.push_back(x);
    slope.push_back((n * sxy - sx * sy) / (n * sxx - sx * sx));
  }
  for (std::size_t k = slope.size(); k-- > 1;) {
    if (slope[k - 1] >= 0.5 && slope[k] < 0.5) {
      const double t = (slope[k - 1] - 0.5) / (slope[k - 1] - slope[k]);
      const double phi_j = phi[k - 1] + t * (phi[k] - phi[k - 1]);
      return {phi_j,
              fmt::format("from the data: d ln p / d ln rate crosses 1/2 at phi {:.4f}", phi_j)};
    }
  }
  throw FitError(
      "fit: no start from the data: d ln p / d ln rate never crosses 1/2 (no crossover from "
      "p ~ rate to a rate-independent p at these rates and packings)");
}

struct Fitted {
  Solution solution;
  std::vector<Point> points;
  int iterations = 0;
  std::string start;
  bool cycled = false;  // settled as a cycle of the point set, not a fixed point
  double chi2_per_dof() const {
    return solution.chi2 / static_cast<double>(points.size() - solution.par.size());
  }
};

/// The first minimisation: starts around the data's start, each minimised on the same point
/// set (chosen at the central start); the best chi^2 wins.
Solution multistart(const std::vector<Point>& points, std::vector<double> central,
                    const std::vector<std::size_t>& free, const ScalingFitOptions& o) {
  const bool phi_free = !o.fixed_phi_j, a_free = !o.fixed_inv_znu;
  std::vector<double> phis = {central[kPhiJ]}, as = {central[kA]};
  if (phi_free)
    phis = {central[kPhiJ], central[kPhiJ] - o.half_window / 3, central[kPhiJ] + o.half_window / 3};
  if (a_free) as = {central[kA], 0.25, 1.0};
  Solution best;
  best.chi2 = std::numeric_limits<double>::infinity();
  std::string last = "no start converged";
  for (double phi0 : phis) {
    for (double a0 : as) {
      Problem pr{points, central, free};
      pr.full[kPhiJ] = phi0;
      pr.full[kA] = a0;
      linear_start(pr);
      try {
        const Solution s = solve(pr);
        if (s.chi2 < best.chi2) best = s;
      } catch (const FitError& e) {
        last = e.what();
      }
    }
  }
  if (!std::isfinite(best.chi2)) throw FitError(last);
  return best;
}

/// The outer iteration: window centred on the current phi_J, point set chosen at the current
/// parameters and held while the minimiser runs, until both stop changing. The first
/// minimisation takes the whole window (no estimate of 1/(z nu) to cut |x| with yet). The
/// grid is discrete, so a window edge can flip a point in and out for ever: a cycle whose
/// last four phi_J lie within five tolerances also counts as settled.
Fitted iterate_window(const std::vector<FitEnsemble>& ens, const Means& m,
                      const ScalingFitOptions& o, std::vector<double> par,
                      const std::vector<std::size_t>& free) {
  Fitted f;
  std::vector<double> history;
  for (int it = 1; it <= o.max_iterations; ++it) {
    const std::vector<Point> pts =
        it == 1 ? candidates(ens, m, o, par[kPhiJ]) : point_set(ens, m, o, par);
    if (pts.size() <= free.size()) {
      throw FitError(
          fmt::format("fit: {} points in the window phi {:.4f} +- {:g} for {} free "
                      "parameters",
                      pts.size(), par[kPhiJ], o.half_window, free.size()));
    }
    const double centre = par[kPhiJ];
    Problem pr{pts, par, free};
    f.solution = it == 1 ? multistart(pts, par, free, o) : solve(pr);
    par = f.solution.par;
    history.push_back(par[kPhiJ]);
    const std::size_t h = history.size();
    const bool settled = it > 1 && std::abs(par[kPhiJ] - centre) < o.tolerance &&
                         same_points(point_set(ens, m, o, par), pts);
    const bool cycle = h >= 4 && *std::max_element(history.end() - 4, history.end()) -
                                         *std::min_element(history.end() - 4, history.end()) <
                                     5 * o.tolerance;
    if (settled || cycle) {
      f.points = pts;
      f.iterations = it;
      f.cycled = !settled;
      return f;
    }
  }
  std::string last;
  for (std::size_t k = history.size() > 3 ? history.size() - 3 : 0; k < history.size(); ++k)
    last += fmt::format("{}{:.5f}", last.empty() ? "" : ", ", history[k]);
  throw FitError(fmt::format("fit: the window did not settle in {} iterations (phi_J last {})",
                             o.max_iterations, last));
}

void check_bounds(const std::vector<double>& par, const ScalingFitOptions& o) {
  if (!o.fixed_rate_exponent && (par[kRateExponent] < kBound || par[kRateExponent] > 1 - kBound)) {
    throw FitError(fmt::format("fit ends on a bound: q = {:.6g} (0 < q < 1)", par[kRateExponent]));
  }
  if (!o.fixed_inv_znu && (par[kA] < kBound || par[kA] > 1 / kBound)) {
    throw FitError(fmt::format("fit ends on a bound: 1/(z nu) = {:.6g} (> 0)", par[kA]));
  }
}

std::vector<double> derived(const std::vector<double>& par) {
  return {par[kPhiJ], par[kRateExponent], par[kA], (1.0 - par[kRateExponent]) / par[kA],
          par[kRateExponent] / par[kA]};
}

}  // namespace

ScalingFitResult fit_scaling(const std::vector<FitEnsemble>& ens, const ScalingFitOptions& o) {
  if (o.order < 0 || o.order > 9)
    throw FitError(fmt::format("fit: polynomial order {} (0..9)", o.order));
  gsl_set_error_handler_off();
  const Means full_means = ensemble_means(ens, std::numeric_limits<std::int64_t>::min());

  // The start: held values where given, the data's crossover otherwise; q and ln f from the
  // linear sub-problem at 1/(z nu) = 1/2 (the middle of its usual range) unless held.
  std::vector<double> par(kC0 + static_cast<std::size_t>(o.order) + 1, 0.0);
  std::string start;
  if (o.fixed_phi_j) {
    par[kPhiJ] = *o.fixed_phi_j;
    start = fmt::format("phi_J held at {:g}", *o.fixed_phi_j);
  } else {
    std::tie(par[kPhiJ], start) = crossover(ens, full_means, o);
  }
  par[kRateExponent] = o.fixed_rate_exponent.value_or(0.5);
  par[kA] = o.fixed_inv_znu.value_or(0.5);
  std::vector<std::size_t> free;
  std::vector<std::string> fixed;
  (o.fixed_phi_j ? fixed.push_back("phi_J") : free.push_back(kPhiJ));
  (o.fixed_rate_exponent ? fixed.push_back("q") : free.push_back(kRateExponent));
  (o.fixed_inv_znu ? fixed.push_back("1/(z nu)") : free.push_back(kA));
  for (std::size_t k = kC0; k < par.size(); ++k) free.push_back(k);
  {
    Problem pr{candidates(ens, full_means, o, par[kPhiJ]), par, free};
    if (pr.points.size() <= free.size()) {
      throw FitError(
          fmt::format("fit: {} points in the window phi {:.4f} +- {:g}, rate <= {:g}, "
                      "for {} free parameters",
                      pr.points.size(), par[kPhiJ], o.half_window, o.rate_max, free.size()));
    }
    linear_start(pr);
    par = pr.full;
  }
  // Several starts of the window iteration: the data's start and a third of the half window
  // either side. The iteration can settle on a spurious fixed point (on paper-2d's +-0.03 window
  // one at phi_J 0.8477, chi^2/dof 174, beside the fit at 0.8408 with 0.53): the best chi^2/dof
  // is kept, and every distinct one found is named in `start`.
  std::vector<double> offsets = {0.0};
  if (!o.fixed_phi_j) offsets = {0.0, -o.half_window / 3, o.half_window / 3};
  std::vector<Fitted> settled;
  std::string last_error;
  for (double d : offsets) {
    std::vector<double> p0 = par;
    p0[kPhiJ] += d;
    try {
      settled.push_back(iterate_window(ens, full_means, o, p0, free));
    } catch (const FitError& e) {
      if (d == 0.0) last_error = e.what();
    }
  }
  if (settled.empty()) throw FitError(last_error);
  const Fitted fit = *std::min_element(settled.begin(), settled.end(), [](auto& a, auto& b) {
    return a.chi2_per_dof() < b.chi2_per_dof();
  });
  std::string distinct;
  for (const Fitted& f : settled) {
    if (std::abs(f.solution.par[kPhiJ] - fit.solution.par[kPhiJ]) > 10 * o.tolerance)
      distinct += fmt::format("{}phi_J {:.5f} at chi^2/dof {:.3g}", distinct.empty() ? "" : ", ",
                              f.solution.par[kPhiJ], f.chi2_per_dof());
  }
  if (!distinct.empty())
    start += fmt::format("; of {} starts, other fixed points: {} (kept the best, phi_J {:.5f})",
                         settled.size(), distinct, fit.solution.par[kPhiJ]);
  if (fit.cycled)
    start +=
        "; the window settled as a cycle of its point set (phi_J within 5 tolerances "
        "over 4 iterations), not a fixed point";
  const Solution& best = fit.solution;
  check_bounds(best.par, o);

  ScalingFitResult r;
  r.start = start;
  r.iterations = fit.iterations;
  r.phi_min = best.par[kPhiJ] - o.half_window;
  r.phi_max = best.par[kPhiJ] + o.half_window;
  r.points = fit.points.size();
  r.free_parameters = free.size();
  const double dof = static_cast<double>(r.points - r.free_parameters);
  r.chi2_diag_per_dof = best.chi2 / dof;
  r.condition_number = best.rcond > 0 ? 1.0 / best.rcond : std::numeric_limits<double>::infinity();
  r.coefficients.assign(best.par.begin() + kC0, best.par.end());
  for (std::size_t k = 0; k < fixed.size(); ++k) r.fixed += (k ? ", " : "") + fixed[k];
  const std::vector<double> plain = derived(best.par);
  r.phi_j_plain = plain[0];
  r.rate_exponent_plain = plain[1];
  r.inv_znu_plain = plain[2];
  r.beta_plain = plain[3];
  r.y_plain = plain[4];
  {
    std::map<std::size_t, std::size_t> per_rate;
    for (std::size_t e = 0; e < ens.size(); ++e)
      if (fitted_rate(ens[e], o)) per_rate[e] = 0;
    for (const Point& p : fit.points) ++per_rate[p.ensemble];
    r.min_points_per_rate =
        per_rate.empty() ? 0
                         : std::min_element(per_rate.begin(), per_rate.end(), [](auto& a, auto& b) {
                             return a.second < b.second;
                           })->second;
  }

  // Sample ids (a sample is left out of every rate at once) and chi^2 with the covariance.
  std::set<std::int64_t> ids;
  for (const auto& e : ens)
    for (auto id : e.sample_ids) ids.insert(id);
  r.samples = ids.size();
  {
    std::vector<std::vector<double>> deviations;
    for (auto id : ids) {
      std::vector<double> row;
      for (const Point& p : fit.points) {
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
    for (const Point& p : fit.points)
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

  std::vector<double> est = plain, err(5, 0.0);
  if (o.jackknife && ids.size() >= 2) {
    const std::vector<std::int64_t> id_list(ids.begin(), ids.end());
    std::vector<std::vector<double>> replicas;
    for (auto id : id_list) {
      const Means m = ensemble_means(ens, id);
      Problem pr{fit.points, best.par, free};
      for (Point& p : pr.points) p.ln_p = std::log(m.mean[p.ensemble][p.index]);  // same weights
      replicas.push_back(derived(solve(pr).par));
    }
    const JackknifeResult j = jackknife(
        id_list.size(), [&](std::size_t k) { return k == id_list.size() ? plain : replicas[k]; });
    est = j.estimate;
    err = j.error;
    r.error_method = JackknifeResult::kMethod;
  } else {
    r.error_method = "none (jackknife off or fewer than 2 samples)";
  }
  // Held parameters are exact, and so are the exponents they determine.
  if (o.fixed_phi_j) est[0] = *o.fixed_phi_j, err[0] = 0.0;
  if (o.fixed_rate_exponent) est[1] = *o.fixed_rate_exponent, err[1] = 0.0;
  if (o.fixed_inv_znu) est[2] = *o.fixed_inv_znu, err[2] = 0.0;
  if (o.fixed_rate_exponent && o.fixed_inv_znu) {
    est[3] = (1.0 - est[1]) / est[2], err[3] = 0.0;
    est[4] = est[1] / est[2], err[4] = 0.0;
  }
  r.phi_j = est[0];
  refuse_outside_compressed_range(ens, o, r.phi_j);
  r.rate_exponent = est[1];
  r.inv_znu = est[2];
  r.beta = est[3];
  r.y = est[4];
  r.phi_j_err = err[0];
  r.rate_exponent_err = err[1];
  r.inv_znu_err = err[2];
  r.beta_err = err[3];
  r.y_err = err[4];

  // The quality flag: a result, but one to read with care.
  std::vector<std::string> poor;
  const double ratio = r.chi2_cov_per_dof / r.chi2_diag_per_dof;
  if (std::isfinite(ratio) &&
      (ratio > kChi2DisagreementFactor || ratio < 1.0 / kChi2DisagreementFactor)) {
    poor.push_back(
        fmt::format("chi^2/dof with the covariance ({:.3g}) and with diagonal errors "
                    "({:.3g}) differ by more than a factor {:g}",
                    r.chi2_cov_per_dof, r.chi2_diag_per_dof, kChi2DisagreementFactor));
  }
  const double chi2 = std::isfinite(r.chi2_cov_per_dof) ? r.chi2_cov_per_dof : r.chi2_diag_per_dof;
  if (chi2 > kMaxChi2PerDof) {
    poor.push_back(
        fmt::format("chi^2/dof {:.3g} above {:g}: the scaling form does not describe these points",
                    chi2, kMaxChi2PerDof));
  }
  if (r.condition_number > kIllConditioned) {
    poor.push_back(fmt::format("ill-conditioned Jacobian (condition number {:.2g} > {:g})",
                               r.condition_number, kIllConditioned));
  }
  if (r.min_points_per_rate < kMinPointsPerRate) {
    poor.push_back(fmt::format("a fitted rate has only {} points in the window (fewer than {})",
                               r.min_points_per_rate, kMinPointsPerRate));
  }
  for (const auto& [name, value, error] :
       {std::tuple{"beta", r.beta, r.beta_err}, std::tuple{"y", r.y, r.y_err}}) {
    if (error > kMaxRelativeError * std::abs(value))
      poor.push_back(fmt::format("uninformative: {} {:.3g} +- {:.3g}, an error above {:g}% of it",
                                 name, value, error, 100 * kMaxRelativeError));
  }
  if (!poor.empty()) {
    r.quality = "poor";
    for (std::size_t k = 0; k < poor.size(); ++k) r.quality_reason += (k ? "; " : "") + poor[k];
  }

  // The collapse, for every point of every rate, with the plain fit's parameters.
  std::set<std::pair<std::size_t, std::size_t>> used;
  for (const Point& p : fit.points) used.insert({p.ensemble, p.index});
  for (std::size_t e = 0; e < ens.size(); ++e) {
    for (std::size_t k = 0; k < ens[e].phi.size(); ++k) {
      const double p = full_means.mean[e][k], dp = full_means.error[e][k];
      if (!(p > 0)) continue;
      const double ln_rate = std::log(ens[e].rate);
      const double scale = std::exp(-best.par[kRateExponent] * ln_rate);
      r.collapse.push_back({ens[e].rate, ens[e].phi[k],
                            scaling_variable(best.par, ens[e].phi[k], ln_rate), p * scale,
                            dp * scale, used.count({e, k}) > 0});
    }
  }
  return r;
}

}  // namespace jam::stats
