#pragma once
// A stabilised explicit integrator for the overdamped equation of motion: the second-order
// Runge-Kutta-Chebyshev method (chebyshev_coefficients.hpp) with an embedded error estimate
// and step-size control. Linearised, the dynamics is de/dt = -G^-1 H e with a real,
// non-positive spectrum bounded by lambda_max (sim/dynamics/stability.hpp): s stages keep a
// step of size h stable while h lambda_max <= beta(s) ~ 0.65 s^2, so the step is limited by
// accuracy, not stability, and the work per unit time falls as ~ 1/sqrt(h).
//
// Slopes in scaled coordinates, ds_i/dt = f_i^el(t) / (gamma_i L(t)): affine motion is exact.
// Stages are kept as displacements from y_n (never wrapped), and positions wrap(s0 + Delta)
// are handed to the force loop, so stages that cross the periodic boundary combine correctly.
//
// Error control (Sommeijer, Shampine and Verwer 1998): after a step,
//   est = (1/15) [12 (y_n - y_{n+1}) + 6 h (F(t_n, y_n) + F(t_{n+1}, y_{n+1}))]
// estimates the local error; err = max_i |est_i| L / tolerance (a physical length: the largest
// error of one particle's displacement in one step) or, with set_error_norm_rms, the root mean
// square over the particles of |est_i| L / tolerance (the RKC code's own norm). The largest
// error is set by the one rearrangement anywhere in the box, so its steps shorten as N grows;
// the observables are means over the particles, and their error follows the mean square
// (docs/performance.md, "The error norm"). err <= 1 accepts, with the next step
// h (0.8 err^(-1/3)) clamped to [h/10, 10 h]; err > 1 rejects and retries with the shorter step.
// F(t_{n+1}, y_{n+1}) is the next step's first slope.
//
// The stages come from lambda_max at y_n: either the Gershgorin bound of the contact network,
// every step (stable by construction), or (set_stiffest_mode_estimate) 1.2 times a Lanczos
// estimate (stiffest_mode_estimate.hpp), renewed every 25 accepted steps and when a step is
// rejected twice, after the RKC code of Sommeijer et al. (1998), which renews its power-method
// estimate every 25 steps with the same factor (and after every rejection: here a single
// rejection, which near jamming follows a rearrangement, not an instability, renewed it for
// nothing at a cost of 20% of the run). The bound is about twice lambda_max on jammed
// packings, and stages grow as sqrt(h lambda): the estimate saves ~1.25x of the force
// evaluations. An estimate that falls behind a stiffening network lets the stiffest modes grow
// until the error estimate rejects the step: accuracy stays under error control either way.
//
// Continuous extension (dense output; Sommeijer et al. 1998 give RKC the same): within the last
// accepted step, y(t_n + theta h) is the cubic Hermite interpolant of y_n, y_{n+1} and their
// slopes F_n, F_{n+1} (all at hand, no extra force evaluation):
//   y(theta) = y_n + theta h F_n + theta^2 [3 Delta - h (2 F_n + F_{n+1})]
//              + theta^3 [-2 Delta + h (F_n + F_{n+1})],   Delta = y_{n+1} - y_n.
// Its cubic coefficient is (15/6) est, so the quadratic interpolant through y_n, F_n, y_{n+1}
// differs from it by at most (4/27)(15/6)|est| = 0.37 err tolerance (at theta = 2/3): an
// accepted step's extension carries the step's own error bound, and output points need not cut
// the step (tests/test_chebyshev.cpp measures it against a step landed at t_n + theta h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

#include "sim/dynamics/chebyshev_coefficients.hpp"
#include "sim/dynamics/position_update.hpp"
#include "sim/dynamics/stability.hpp"
#include "sim/dynamics/stepper_state.hpp"
#include "sim/dynamics/stiffest_mode_estimate.hpp"
#include "sim/dynamics/system.hpp"
#include "sim/parallel.hpp"

namespace jam {

template <int D>
class OverdampedChebyshev {
 public:
  static constexpr const char* kName = "chebyshev";
  static constexpr int kOrder = 2;
  static constexpr bool kAdaptive = true;

  /// `tolerance`: the local error of the displacements allowed per step (d_s; the largest
  /// component, or the root mean square over the particles after set_error_norm_rms);
  /// `first_step`: the first step tried (t0), after which the controller takes over.
  OverdampedChebyshev(std::size_t n, const StepperOptions& o)
      : OverdampedChebyshev(n, o.tolerance, o.first_step) {}
  OverdampedChebyshev(std::size_t n, double tolerance, double first_step)
      : tolerance_(tolerance), first_step_(first_step), h_next_(first_step) {
    for (int d = 0; d < D; ++d) {
      s0_[d].resize(n);
      f0_[d].resize(n);
      f1_[d].resize(n);
      delta1_[d].resize(n);
      delta2_[d].resize(n);
    }
  }

  /// The tolerance from here on (the compression's may differ from the relaxation's).
  void set_tolerance(double tolerance) { tolerance_ = tolerance; }

  /// lambda_max from here on: the Lanczos estimate (true) or the Gershgorin bound (false, the
  /// default).
  void set_stiffest_mode_estimate(bool estimate) { estimate_ = estimate; }

  /// The error norm from here on: root mean square over the particles (true) or the largest
  /// component (false, the default).
  void set_error_norm_rms(bool rms) { rms_ = rms; }

  /// After relaxation: the next step starts from the first step again.
  void reset() {
    h_next_ = first_step_;
    have_f0_ = false;
    have_estimate_ = false;
  }
  StepperState save_state() const {
    StepperState state{{"h_next", {h_next_}}};
    if (have_estimate_)
      state.push_back({"stiffest_mode", {rho_estimate_, static_cast<double>(since_estimate_)}});
    return state;
  }
  void load_state(const StepperState& state) {
    have_estimate_ = false;
    for (const auto& [name, values] : state) {
      if (name == "h_next" && values.size() == 1) h_next_ = values[0];
      if (name == "stiffest_mode" && values.size() == 2) {
        rho_estimate_ = values[0];
        since_estimate_ = static_cast<int>(values[1]);
        have_estimate_ = true;
      }
    }
    have_f0_ = false;  // recomputed from y_n: the same bits
  }

  /// One accepted step from t of at most h_max (rejected tries are retried shorter); returns
  /// the step taken. Particles end at y(t + h).
  template <class Contact>
  double step(System<D, Contact>& sys, double t, double h_max) {
    begin_step(sys, t);
    double rho = stiffest_mode_rate(sys, t, 0);
    double h = std::min(h_next_, h_max);
    for (int rejected = 0;;) {
      int s = chebyshev_stages(h * rho);
      const double beta = chebyshev_stability_interval(s);
      if (h * rho > beta) h = 0.95 * beta / rho;  // beyond the most stages: a shorter step
      const double err = try_step(sys, t, h, coefficients(s));
      ++stats_.attempts;
      stats_.stages += static_cast<std::uint64_t>(s);
      const double factor = err > 0.0 ? 0.8 * std::pow(err, -1.0 / 3.0) : 10.0;
      if (err <= 1.0) {
        ++since_estimate_;
        std::swap(f0_, f1_);  // the slope at y_{n+1}, first slope of the next step
        have_f0_ = true;
        last_t_ = t, last_h_ = h;
        // A step cut short to land on an output time does not shrink the next one.
        const double proposed = std::clamp(factor, 0.1, kMaxGrowth) * h;
        h_next_ = h == h_max && h < h_next_ ? std::min(h_next_, proposed) : proposed;
        return h;
      }
      ++stats_.rejections;
      h *= std::max(0.1, factor);
      for (int d = 0; d < D; ++d)
        std::copy(s0_[d].begin(), s0_[d].end(), sys.particles.s[d].begin());
      rho = stiffest_mode_rate(sys, t, ++rejected);
    }
  }

  /// The continuous extension of the last accepted step (from t_n, of size h_n) at time t in
  /// [t_n, t_n + h_n]: out[d][i] <- the wrapped scaled position of particle i at t.
  void interpolate(double t, std::array<std::vector<double>, D>& out) const {
    const double h = last_h_, theta = (t - last_t_) / h;
    const HermiteWeights w{h, theta * h, theta * theta, theta * theta * theta};
    // f1_ holds F_n and f0_ holds F_{n+1} after the accepted step's swap; delta1_ = Delta.
    for (int d = 0; d < D; ++d) {
      out[d].resize(s0_[d].size());
      hermite_coordinate(out[d].data(), s0_[d].data(), f1_[d].data(), f0_[d].data(),
                         delta1_[d].data(), w, 0, s0_[d].size());
    }
  }

  /// The start and size of the last accepted step (the range of interpolate()).
  double last_step_start() const { return last_t_; }
  double last_step_size() const { return last_h_; }

  /// One step of size h with s stages and no control (tests: order, stability interval);
  /// returns the error estimate err.
  template <class Contact>
  double fixed_step(System<D, Contact>& sys, double t, double h, int s) {
    begin_step(sys, t);
    const double err = try_step(sys, t, h, coefficients(s));
    std::swap(f0_, f1_);
    have_f0_ = true;
    last_t_ = t, last_h_ = h;
    return err;
  }

  struct Stats {
    std::uint64_t attempts = 0, rejections = 0, stages = 0, estimates = 0;
  };
  const Stats& stats() const { return stats_; }

 private:
  /// The rate the stages must keep stable at y_n (the particles' positions, time t), after
  /// `rejected` rejected tries of this step: the bound (once per step), or the estimate times
  /// kEstimateSafety, renewed when kEstimateEvery steps were accepted since it was taken, or at
  /// the second rejection of a step (unless it was taken at this y_n).
  template <class Contact>
  double stiffest_mode_rate(System<D, Contact>& sys, double t, int rejected) {
    const double length = sys.box.length(t);
    if (!estimate_) {
      if (rejected == 0) bound_ = stiffest_mode_bound(sys, length, sys.species.drag);
      return bound_;
    }
    const bool due = !have_estimate_ || since_estimate_ >= kEstimateEvery ||
                     (rejected >= 2 && since_estimate_ > 0);
    if (due) {
      sys.update_neighbors(length);  // the list of the last force evaluation may be older
      rho_estimate_ = kEstimateSafety * estimator_.estimate(sys, length, sys.species.drag);
      have_estimate_ = true;
      since_estimate_ = 0;
      ++stats_.estimates;
    }
    return rho_estimate_;
  }

  /// y_n and its slope: s0_ <- the positions, f0_ <- F(t, y_n) unless carried over from the
  /// last accepted step (the same bits either way).
  template <class Contact>
  void begin_step(System<D, Contact>& sys, double t) {
    if (!have_f0_) slope(sys, t, f0_);
    for (int d = 0; d < D; ++d)
      std::copy(sys.particles.s[d].begin(), sys.particles.s[d].end(), s0_[d].begin());
  }

  /// out = F(t, current positions) = f^el / (gamma L(t)), scaled units.
  template <class Contact>
  void slope(System<D, Contact>& sys, double t, std::array<std::vector<double>, D>& out) {
    const auto c = forces_at(sys, sys.box.length(t));
    const auto* type = sys.particles.type.data();
    for_particle_chunks(sys.size(), sys.threads(), [&](std::size_t first, std::size_t last) {
      for (int d = 0; d < D; ++d)
        for (std::size_t i = first; i < last; ++i) out[d][i] = c[type[i]] * sys.force[d][i];
    });
  }

  /// The elastic forces at box length L, and the factor per type that makes them slopes:
  /// F_i = c[type_i] f_i^el, c = 1 / (gamma L) (scaled units).
  template <class Contact>
  static std::array<double, 2> forces_at(System<D, Contact>& sys, double length) {
    sys.compute_elastic_forces(length);
    return {sys.species.mobility[0] / length, sys.species.mobility[1] / length};
  }

  /// The s stages from y_n = s0_ (slope f0_) to y_{n+1}, left in the system; returns err.
  /// Each stage's slope, recurrence and placing of the particles at the next stage are one
  /// pass over the particles (three before: the same operations in the same order, the same
  /// bits; 11% of a slow 2D run's time at N = 32768).
  template <class Contact>
  double try_step(System<D, Contact>& sys, double t, double h, const ChebyshevCoefficients& k) {
    const std::size_t n = sys.size();
    const auto* type = sys.particles.type.data();
    // delta1 = Y_1 - Y_0, delta2 = Y_0 - Y_0 = 0; the particles at Y_1.
    const double a1 = k.mu_tilde[1] * h;
    for_particle_chunks(n, sys.threads(), [&](std::size_t first, std::size_t last) {
      for (int d = 0; d < D; ++d) {
        for (std::size_t i = first; i < last; ++i) {
          const double y = a1 * f0_[d][i];
          delta1_[d][i] = y;
          delta2_[d][i] = 0.0;
          sys.particles.s[d][i] = wrap_unit(s0_[d][i] + y);
        }
      }
    });
    for (int j = 2; j <= k.stages; ++j) {
      // F(Y_{j-1}) = c f^el (slope()), then Y_j, and the particles there.
      const auto c = forces_at(sys, sys.box.length(t + k.c[j - 1] * h));
      const double mu = k.mu[j], nu = k.nu[j], a = k.mu_tilde[j] * h, g = k.gamma_tilde[j] * h;
      for_particle_chunks(n, sys.threads(), [&](std::size_t first, std::size_t last) {
        for (int d = 0; d < D; ++d) {
          for (std::size_t i = first; i < last; ++i) {
            const double f = c[type[i]] * sys.force[d][i];
            const double y = mu * delta1_[d][i] + nu * delta2_[d][i] + a * f + g * f0_[d][i];
            delta2_[d][i] = y;
            sys.particles.s[d][i] = wrap_unit(s0_[d][i] + y);
          }
        }
      });
      std::swap(delta1_, delta2_);  // delta1 = Y_j - Y_0, delta2 = Y_{j-1} - Y_0
    }
    slope(sys, t + h, f1_);  // at y_{n+1}, placed by the last stage
    // The local error estimate, as a physical length, over the largest tolerance.
    double worst = 0.0, sum2 = 0.0;
    for (int d = 0; d < D; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        const double e = std::abs(12.0 * -delta1_[d][i] + 6.0 * h * (f0_[d][i] + f1_[d][i]));
        worst = std::max(worst, e);
        sum2 += e * e;
      }
    }
    const double norm = rms_ && n > 0 ? std::sqrt(sum2 / static_cast<double>(n)) : worst;
    return norm / 15.0 * sys.box.length(t + h) / tolerance_;
  }

  const ChebyshevCoefficients& coefficients(int s) {
    auto it = cache_.find(s);
    if (it == cache_.end()) it = cache_.emplace(s, chebyshev_coefficients(s)).first;
    return it->second;
  }

  // Growth of the step after an accepted one: at most 2x (10x, the classical cap, measured 35%
  // of steps rejected at rate 1e-5 in 2D: the error jumps at each rearrangement).
  static constexpr double kMaxGrowth = 2.0;

  // The stiffest-mode estimate's schedule and safety factor (Sommeijer et al. 1998: 25, 1.2).
  static constexpr int kEstimateEvery = 25;
  static constexpr double kEstimateSafety = 1.2;

  double tolerance_, first_step_, h_next_;
  bool estimate_ = false, have_estimate_ = false, rms_ = false;
  double rho_estimate_ = 0.0, bound_ = 0.0;
  int since_estimate_ = 0;
  StiffestModeEstimate<D> estimator_;
  double last_t_ = 0.0, last_h_ = 0.0;  // the last accepted step (interpolate's range)
  bool have_f0_ = false;
  std::array<std::vector<double>, D> s0_, f0_, f1_, delta1_, delta2_;
  std::map<int, ChebyshevCoefficients> cache_;
  Stats stats_;
};

}  // namespace jam
