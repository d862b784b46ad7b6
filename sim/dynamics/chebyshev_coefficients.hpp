#pragma once
// The coefficients of the s-stage second-order Runge-Kutta-Chebyshev method (RKC) of
// Sommeijer, Shampine and Verwer, J. Comput. Appl. Math. 88, 315 (1998), with damping
// eps = 2/13: for y' = F(t, y), one step of size h is
//   Y_0 = y_n,  Y_1 = Y_0 + mu~_1 h F(t_n, Y_0),
//   Y_j = (1 - mu_j - nu_j) Y_0 + mu_j Y_{j-1} + nu_j Y_{j-2}
//         + mu~_j h F(t_n + c_{j-1} h, Y_{j-1}) + gamma~_j h F(t_n, Y_0),   j = 2 ... s,
//   y_{n+1} = Y_s.
// Its stability region contains the real interval [-beta(s), 0] with beta(s) ~ 0.653 s^2 (the
// shifted, damped Chebyshev polynomial T_s(w0 + w1 z) / T_s(w0) stays within 1/(1 + eps/...)
// there), so a step of size h is stable for a spectrum in [-rho, 0] with s ~ sqrt(h rho / 0.653)
// stages: the cost of a unit of time falls as 1/sqrt(h) while accuracy allows a longer step.
#include <cmath>
#include <stdexcept>
#include <vector>

namespace jam {

struct ChebyshevCoefficients {
  int stages = 0;
  // Indexed by stage j = 0 ... s (entries 0 and, for mu, nu, gamma~, 1 unused).
  std::vector<double> mu, nu, mu_tilde, gamma_tilde, c;
  double beta = 0.0;  // length of the real stability interval [-beta, 0]
};

/// Damping of the RKC polynomials (the value of Sommeijer et al.): it shrinks the stability
/// interval by ~2% and keeps |R(z)| <= 1 - eps/... < 1 away from z = 0, so that stiff modes
/// are damped rather than carried.
inline constexpr double kChebyshevDamping = 2.0 / 13.0;

/// The most stages a step may take: beyond a few hundred, round-off in the three-term
/// recursion grows (Verwer et al. keep s below ~ 300); the step is shortened instead.
inline constexpr int kMaxChebyshevStages = 250;

/// beta(s): the edge of the real stability interval of R(z) = a_s + b_s T_s(w0 + w1 z), the
/// method's amplification factor (b_s = T_s''(w0) / T_s'(w0)^2, a_s = 1 - b_s T_s(w0)). Past
/// w0 + w1 z = -1, T_s leaves [-1, 1] with the sign (-1)^s, and |R| = 1 where
/// T_s(x) = (+-1 - a_s) / b_s: x = -w0 for even s (the symmetric point of T_s(w0)), and
/// x = -cosh(acosh(2/b_s - T_s(w0)) / s) for odd s. About (2/3)(s^2 - 1)(1 - (2/15) eps);
/// odd s reach somewhat further.
inline double chebyshev_stability_interval(int s) {
  const double w0 = 1.0 + kChebyshevDamping / (s * s);
  double t0 = 1.0, t1 = w0, d0 = 0.0, d1 = 1.0, e0 = 0.0, e1 = 0.0;
  for (int j = 2; j <= s; ++j) {
    const double t2 = 2.0 * w0 * t1 - t0, d2 = 2.0 * t1 + 2.0 * w0 * d1 - d0,
                 e2 = 4.0 * d1 + 2.0 * w0 * e1 - e0;
    t0 = t1, t1 = t2, d0 = d1, d1 = d2, e0 = e1, e1 = e2;
  }
  const double w1 = d1 / e1, b = e1 / (d1 * d1);
  const double x = s % 2 == 0 ? -w0 : -std::cosh(std::acosh(2.0 / b - t1) / s);
  return (w0 - x) / w1;
}

/// The fewest stages (>= 2) whose stability interval holds h rho with 5% to spare, at most
/// kMaxChebyshevStages.
inline int chebyshev_stages(double h_rho) {
  static const std::vector<double> beta = [] {
    std::vector<double> b(kMaxChebyshevStages + 1, 0.0);
    for (int s = 2; s <= kMaxChebyshevStages; ++s) b[s] = chebyshev_stability_interval(s);
    return b;
  }();
  int s = 2;
  while (s < kMaxChebyshevStages && beta[s] < 1.05 * h_rho) ++s;
  return s;
}

inline ChebyshevCoefficients chebyshev_coefficients(int s) {
  if (s < 2) throw std::invalid_argument("RKC needs at least 2 stages");
  ChebyshevCoefficients k;
  k.stages = s;
  const double w0 = 1.0 + kChebyshevDamping / (s * s);
  // Chebyshev polynomials T_j and their first two derivatives at w0.
  std::vector<double> t(s + 1), dt(s + 1), d2t(s + 1);
  t[0] = 1.0, t[1] = w0;
  dt[0] = 0.0, dt[1] = 1.0;
  d2t[0] = 0.0, d2t[1] = 0.0;
  for (int j = 2; j <= s; ++j) {
    t[j] = 2.0 * w0 * t[j - 1] - t[j - 2];
    dt[j] = 2.0 * t[j - 1] + 2.0 * w0 * dt[j - 1] - dt[j - 2];
    d2t[j] = 4.0 * dt[j - 1] + 2.0 * w0 * d2t[j - 1] - d2t[j - 2];
  }
  const double w1 = dt[s] / d2t[s];
  std::vector<double> b(s + 1), a(s + 1);
  for (int j = 2; j <= s; ++j) b[j] = d2t[j] / (dt[j] * dt[j]);
  b[0] = b[1] = b[2];
  for (int j = 0; j <= s; ++j) a[j] = 1.0 - b[j] * t[j];
  k.mu.assign(s + 1, 0.0);
  k.nu.assign(s + 1, 0.0);
  k.mu_tilde.assign(s + 1, 0.0);
  k.gamma_tilde.assign(s + 1, 0.0);
  k.c.assign(s + 1, 0.0);
  k.mu_tilde[1] = b[1] * w1;
  k.c[1] = k.mu_tilde[1];
  for (int j = 2; j <= s; ++j) {
    k.mu[j] = 2.0 * w0 * b[j] / b[j - 1];
    k.nu[j] = -b[j] / b[j - 2];
    k.mu_tilde[j] = 2.0 * w1 * b[j] / b[j - 1];
    k.gamma_tilde[j] = -a[j - 1] * k.mu_tilde[j];
    // Stage times from the scheme applied to y' = 1 (c_s = 1 up to round-off).
    k.c[j] = k.mu[j] * k.c[j - 1] + k.nu[j] * k.c[j - 2] + k.mu_tilde[j] + k.gamma_tilde[j];
  }
  k.beta = chebyshev_stability_interval(s);
  return k;
}

}  // namespace jam
