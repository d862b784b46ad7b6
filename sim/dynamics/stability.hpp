#pragma once
// Linear stability of explicit time steps on the current contact network.
//
// Linearised about a configuration, the overdamped equation of motion is de/dt = -G^-1 H e,
// with H the Hessian of the elastic energy and G = diag(gamma_i); the inertial one is
// d2e/dt2 = -M^-1 H e (+ drag). Forward Euler and Heun (explicit RK2) are stable for a mode of
// rate lambda only if dt lambda <= 2 (their amplification factors 1 - z and 1 - z + z^2/2 with
// z = dt lambda leave [-1, 1] at z = 2); velocity Verlet is stable for a mode of angular
// frequency omega only if dt omega <= 2. So the stable step is set by the largest eigenvalue
// lambda_max of W^-1/2 H W^-1/2, W = G (overdamped, a rate) or W = M (inertial, omega^2).
//
// The Hessian of a contact is H_ij = U''(r) n n^T + (U'(r)/r)(1 - n n^T) with U'/r = -(f/r)
// <= 0 (contacts only push), so the tangential part is negative semidefinite and
// lambda_max(H) <= lambda_max(H_n) with H_n the radial part alone. U'' comes from the contact
// law (radial_stiffness: 1/d_ij^2 for the harmonic law, (3/2) delta^(1/2)/d_ij^2 for the
// Hertzian one), and "in contact" is the law's one test, the force loop's.
// Both estimates below use H_n: they are upper bounds on the stiffness that stays finite even
// for two particles at the same point. Nothing here changes a particle: these are diagnostics.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/dynamics/system.hpp"

namespace jam {

/// Per-type inertia W of the linearised dynamics: the drag gamma (overdamped, eigenvalues are
/// rates) or the mass m (inertial, eigenvalues are omega^2).
using ModeInertia = std::array<double, 2>;

/// Calls visit(i, j, dr, r2, k_ij) for every listed pair in contact at box length L, dr the
/// minimum-image separation and k_ij = U''(r) the law's radial stiffness. Diagnostics only:
/// not the force loop.
template <int D, class Contact, class Visit>
void for_each_contact(const System<D, Contact>& sys, double box_length, Visit&& visit) {
  const auto& offsets = sys.neighbors.offsets();
  const auto& nbr = sys.neighbors.neighbors();
  const auto& type = sys.particles.type;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const std::uint32_t j = nbr[k];
      std::array<double, D> dr;
      const double r2 = pair_separation(sys.particles, i, j, box_length, dr);
      const int pair = type[i] + type[j];
      if (sys.contact.in_contact(r2, pair)) {
        visit(i, static_cast<std::size_t>(j), dr, r2, sys.contact.radial_stiffness(r2, pair));
      }
    }
  }
}

/// Gershgorin bound on lambda_max(W^-1/2 H_n W^-1/2): max over particles of
/// sum_j k_ij (1/w_i + 1/sqrt(w_i w_j)), k_ij = U''(r_ij) over the contacts of i. One pass
/// over the neighbor list, which must be valid for box length L (the last force evaluation).
template <int D, class Contact>
double stiffest_mode_bound(const System<D, Contact>& sys, double box_length, const ModeInertia& w) {
  const std::size_t n = sys.size();
  const auto& type = sys.particles.type;
  std::vector<double> row(n, 0.0);
  for_each_contact(
      sys, box_length,
      [&](std::size_t i, std::size_t j, const std::array<double, D>&, double, double kij) {
        const double cross = kij / std::sqrt(w[type[i]] * w[type[j]]);
        row[i] += kij / w[type[i]] + cross;
        row[j] += kij / w[type[j]] + cross;
      });
  return n ? *std::max_element(row.begin(), row.end()) : 0.0;
}

/// x[d][i] <- deterministic pseudo-random values in [-0.5, 0.5) for n particles (the same
/// bits on every machine): the start vector of the iterations here and of the Lanczos
/// estimate (stiffest_mode_estimate.hpp).
template <int D>
void deterministic_start_vector(std::array<std::vector<double>, D>& x, std::size_t n) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (int d = 0; d < D; ++d) {
    x[d].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= h >> 31;
      h *= 0xbf58476d1ce4e5b9ULL;
      h ^= h >> 29;
      x[d][i] = static_cast<double>(h >> 11) * 0x1.0p-53 - 0.5;
    }
  }
}

/// lambda_max(W^-1/2 H_n W^-1/2) by power iteration (Rayleigh quotient after `iterations`
/// products; H_n is positive semidefinite, so the iteration converges to the top of the
/// spectrum from below). Deterministic start vector. Same list requirement as above.
template <int D, class Contact>
double stiffest_mode(const System<D, Contact>& sys, double box_length, const ModeInertia& w,
                     int iterations = 60) {
  const std::size_t n = sys.size();
  const auto& type = sys.particles.type;
  std::array<std::vector<double>, D> x, y;
  deterministic_start_vector<D>(x, n);
  for (int d = 0; d < D; ++d) y[d].assign(n, 0.0);
  auto norm2 = [&](const std::array<std::vector<double>, D>& v) {
    double s = 0.0;
    for (int d = 0; d < D; ++d)
      for (double e : v[d]) s += e * e;
    return s;
  };
  // y = W^-1/2 H_n W^-1/2 x
  auto apply = [&]() {
    for (int d = 0; d < D; ++d) std::fill(y[d].begin(), y[d].end(), 0.0);
    for_each_contact(
        sys, box_length,
        [&](std::size_t i, std::size_t j, const std::array<double, D>& dr, double r2, double k) {
          if (r2 == 0.0) return;  // r = 0: no direction, no radial stiffness
          const double si = 1.0 / std::sqrt(w[type[i]]);
          const double sj = 1.0 / std::sqrt(w[type[j]]);
          double proj = 0.0;
          for (int a = 0; a < D; ++a) proj += dr[a] * (si * x[a][i] - sj * x[a][j]);
          const double c = k * proj / r2;  // k (n . u) / r
          for (int a = 0; a < D; ++a) {
            y[a][i] += si * c * dr[a];
            y[a][j] -= sj * c * dr[a];
          }
        });
  };
  double lambda = 0.0;
  for (int it = 0; it < iterations; ++it) {
    const double xx = norm2(x);
    if (!(xx > 0.0)) return lambda;
    apply();
    double xy = 0.0;
    for (int d = 0; d < D; ++d)
      for (std::size_t i = 0; i < n; ++i) xy += x[d][i] * y[d][i];
    lambda = xy / xx;
    const double scale = 1.0 / std::sqrt(norm2(y));
    if (!std::isfinite(scale)) return lambda;
    for (int d = 0; d < D; ++d)
      for (std::size_t i = 0; i < n; ++i) x[d][i] = scale * y[d][i];
  }
  return lambda;
}

}  // namespace jam
