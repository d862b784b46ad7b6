#pragma once
// An estimate of lambda_max(W^-1/2 H_n W^-1/2), the rate of the stiffest contact mode
// (stability.hpp), from a few Lanczos steps: what the Chebyshev integrator's stages need,
// closer than the Gershgorin bound. On jammed 2D packings the bound is about twice lambda_max
// (measured on an N = 32768 packing at phi 0.805: bound 10.0, lambda_max 4.84 from a sparse
// eigensolver), and the stages of a step grow as sqrt(h lambda), so the bound costs ~1.4x in
// force evaluations wherever steps are long (docs/performance.md, "The stiffest mode").
//
// Lanczos on A = W^-1/2 H_n W^-1/2 (symmetric positive semidefinite): after m steps the
// largest eigenvalue of the tridiagonal matrix, the largest Ritz value, lies at or below
// lambda_max (up to round-off; it approaches from below, and loss of orthogonality only adds
// copies of converged values), and converges to it far faster than the power method (the same
// packing: 0.99 of lambda_max after 20 steps, 0.999 after 30; power iteration 0.955 after 20).
// The integrator multiplies it by a safety factor (overdamped_chebyshev.hpp), as the RKC code of
// Sommeijer, Shampine and Verwer (1998) does with its power-method estimate.
//
// The contacts are gathered once per estimate (i, j, sqrt(k) n, the particles' W^-1/2); each
// Lanczos step is then one pass over them. Diagnostics of the current configuration: nothing
// here moves a particle.
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/dynamics/mode_product_terms.hpp"
#include "sim/dynamics/stability.hpp"
#include "sim/dynamics/system.hpp"

namespace jam {

template <int D>
class StiffestModeEstimate {
 public:
  /// Lanczos steps per estimate (the largest Ritz value after 30 steps: 0.999 lambda_max on
  /// the packing above; tests/test_stiffest_mode_estimate.cpp measures it on others).
  static constexpr int kLanczosSteps = 30;

  /// The largest Ritz value of A on the contacts of `sys` at box length L (0 without
  /// contacts). The neighbor list must be valid for L and the current positions.
  template <class Contact>
  double estimate(const System<D, Contact>& sys, double box_length, const ModeInertia& w,
                  int steps = kLanczosSteps) {
    gather_contacts(sys, box_length, w);
    const std::size_t n = sys.size();
    if (contacts() == 0 || n == 0) return 0.0;
    start_vector(n);
    std::vector<double> alpha, beta;
    double b = 0.0;
    for (int m = 0; m < steps; ++m) {
      apply(q_, v_);  // v = A q_m - beta_{m-1} q_{m-1}
      for (int d = 0; d < D; ++d)
        for (std::size_t i = 0; i < n; ++i) v_[d][i] -= b * q_prev_[d][i];
      const double a = dot(q_, v_);
      for (int d = 0; d < D; ++d)
        for (std::size_t i = 0; i < n; ++i) v_[d][i] -= a * q_[d][i];
      alpha.push_back(a);
      b = std::sqrt(dot(v_, v_));
      // An invariant subspace (b ~ 0, e.g. a few particles in contact): the Ritz values are
      // eigenvalues; stop there.
      if (m + 1 == steps || !(b > 1e-12 * std::abs(a))) break;
      beta.push_back(b);
      std::swap(q_prev_, q_);
      for (int d = 0; d < D; ++d)
        for (std::size_t i = 0; i < n; ++i) q_[d][i] = v_[d][i] / b;
    }
    return largest_ritz_value(alpha, beta);
  }

  /// Contacts of the last estimate.
  std::size_t contacts() const { return ci_.size(); }

 private:
  /// ci_, cj_, g = sqrt(k_ij) n_ij and W^-1/2 of both partners, for every contact.
  template <class Contact>
  void gather_contacts(const System<D, Contact>& sys, double box_length, const ModeInertia& w) {
    ci_.clear(), cj_.clear(), ai_.clear(), aj_.clear();
    for (auto& g : g_) g.clear();
    const auto& type = sys.particles.type;
    const std::array<double, 2> a = {1.0 / std::sqrt(w[0]), 1.0 / std::sqrt(w[1])};
    for_each_contact(
        sys, box_length,
        [&](std::size_t i, std::size_t j, const std::array<double, D>& dr, double r2, double k) {
          if (r2 == 0.0) return;  // r = 0: no direction, no radial stiffness
          const double s = std::sqrt(k / r2);
          ci_.push_back(static_cast<std::uint32_t>(i));
          cj_.push_back(static_cast<std::uint32_t>(j));
          ai_.push_back(a[type[i]]);
          aj_.push_back(a[type[j]]);
          for (int d = 0; d < D; ++d) g_[d].push_back(s * dr[d]);
        });
  }

  /// A deterministic start (the same bits on every machine), normalized.
  void start_vector(std::size_t n) {
    deterministic_start_vector<D>(q_, n);
    for (int d = 0; d < D; ++d) {
      q_prev_[d].assign(n, 0.0);
      v_[d].resize(n);
    }
    const double norm = std::sqrt(dot(q_, q_));
    for (int d = 0; d < D; ++d)
      for (double& e : q_[d]) e /= norm;
  }

  /// y = A x = sum over contacts of g g^T (a_i x_i - a_j x_j), added to i with a_i and
  /// taken from j with a_j. Each block's per-contact terms first (mode_product_terms.hpp,
  /// packed), then the sums: the contacts come in rows (all of particle i's with j > i in a
  /// run), y_i is summed in registers along its run. The same additions in the same order as
  /// one contact at a time, so the same bits.
  void apply(const std::array<std::vector<double>, D>& x, std::array<std::vector<double>, D>& y) {
    for (int d = 0; d < D; ++d) std::fill(y[d].begin(), y[d].end(), 0.0);
    const auto m = static_cast<std::uint32_t>(ci_.size());
    ModeProductInput<D> in{
        .ci = ci_.data(), .cj = cj_.data(), .ai = ai_.data(), .aj = aj_.data(), .g = {}, .x = {}};
    for (int d = 0; d < D; ++d) in.g[d] = g_[d].data(), in.x[d] = x[d].data();
    ModeTermsBlock<D> terms;
    for (std::uint32_t c0 = 0; c0 < m; c0 += kModeBlockContacts) {
      const std::uint32_t c1 = std::min(m, c0 + kModeBlockContacts);
      mode_terms(in, c0, c1, terms);
      for (std::uint32_t c = c0; c < c1;) {
        const std::uint32_t i = ci_[c];
        std::array<double, D> yi;
        for (int d = 0; d < D; ++d) yi[d] = y[d][i];
        for (; c < c1 && ci_[c] == i; ++c) {  // j != i within the run: y_i is not touched there
          const std::uint32_t j = cj_[c];
          for (int d = 0; d < D; ++d) {
            yi[d] += terms.to_i[d][c - c0];
            y[d][j] -= terms.to_j[d][c - c0];
          }
        }
        for (int d = 0; d < D; ++d) y[d][i] = yi[d];
      }
    }
  }

  /// x . y in four interleaved partial sums (a fixed order: the same bits every time; one
  /// running sum is bound by the latency of its additions).
  static double dot(const std::array<std::vector<double>, D>& x,
                    const std::array<std::vector<double>, D>& y) {
    double s[4] = {0.0, 0.0, 0.0, 0.0};
    for (int d = 0; d < D; ++d) {
      const double* a = x[d].data();
      const double* b = y[d].data();
      const std::size_t n = x[d].size();
      std::size_t i = 0;
      for (; i + 4 <= n; i += 4)
        for (int u = 0; u < 4; ++u) s[u] += a[i + u] * b[i + u];
      for (; i < n; ++i) s[0] += a[i] * b[i];
    }
    return (s[0] + s[1]) + (s[2] + s[3]);
  }

  /// The largest eigenvalue of the symmetric tridiagonal matrix (alpha on the diagonal, beta
  /// beside it), by Eigen's tridiagonal QR.
  static double largest_ritz_value(const std::vector<double>& alpha,
                                   const std::vector<double>& beta) {
    const auto m = static_cast<Eigen::Index>(alpha.size());
    Eigen::VectorXd diag = Eigen::Map<const Eigen::VectorXd>(alpha.data(), m);
    Eigen::VectorXd sub = Eigen::VectorXd::Zero(m > 1 ? m - 1 : 1);
    for (Eigen::Index k = 0; k + 1 < m; ++k) sub[k] = beta[static_cast<std::size_t>(k)];
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
    es.computeFromTridiagonal(diag, sub.head(m > 1 ? m - 1 : 0), Eigen::EigenvaluesOnly);
    return es.eigenvalues().maxCoeff();
  }

  std::vector<std::uint32_t> ci_, cj_;
  std::vector<double> ai_, aj_;
  std::array<std::vector<double>, D> g_, q_, q_prev_, v_;
};

}  // namespace jam
