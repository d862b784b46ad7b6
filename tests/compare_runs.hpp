#pragma once
// Synthetic ensembles for the compare check (checks/compare_check.hpp) on any output grid:
// S runs of p(phi) = exp(30 (phi - 0.84)) (1 + shift) exp(eps(phi)) on the multiples of a
// step in [0.80, 0.86], eps an Ornstein-Uhlenbeck process along phi (the relative scatter of
// one run, correlation 0.9 per 0.001 in phi, as synthetic_runs.hpp, whatever the step), and
// the same at constant Z (p(Z) = exp(5 (Z - 4.2)) ..., Z in [3.8, 4.6], correlation length
// 0.1 in Z); jamming points drawn around a mean when asked. Used by tests/test_compare_check.cpp
// and bench/compare_error_rates.cpp.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "checks/stats_data.hpp"

namespace jam::checks::testing {

/// The multiples of `step` in [lo, hi], shifted by `offset` (a grid of another code's outputs).
inline std::vector<double> step_grid(double lo, double hi, double step, double offset = 0.0) {
  std::vector<double> g;
  for (auto k = static_cast<std::int64_t>(std::ceil((lo - offset) / step - 1e-9));
       static_cast<double>(k) * step + offset <= hi + 1e-12; ++k)
    g.push_back(static_cast<double>(k) * step + offset);
  return g;
}

struct EnsembleDesign {
  std::int64_t n = 256;
  double phi_init = 0.4, log10_rate = -5;
  int samples = 10;
  double phi_step = 0.0005, phi_offset = 0.0, z_step = 0.01;
  double scatter = 0.05;                              // relative scatter of one run's pressure
  double shift = 0.0;                                 // the pressure multiplied by 1 + shift
  double jamming_mean = NAN, jamming_spread = 0.003;  // phi_Ji ~ N(mean, spread) when finite
  std::int64_t first_id = 0;
};

/// One run's pressure on `grid`: base(x) (1 + shift) exp(eps(x)), eps an OU process of
/// amplitude `scatter` and correlation length `length`.
template <class Base>
std::vector<double> correlated_run(const std::vector<double>& grid, Base base, double shift,
                                   double scatter, double length, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> row;
  double eps = scatter * g(rng);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    if (k > 0) {
      const double rho = std::exp(-(grid[k] - grid[k - 1]) / length);
      eps = rho * eps + scatter * std::sqrt(1 - rho * rho) * g(rng);
    }
    row.push_back(base(grid[k]) * (1 + shift) * std::exp(eps));
  }
  return row;
}

inline EnsembleTables synthetic_ensemble(const EnsembleDesign& d, std::mt19937_64& rng) {
  EnsembleTables e;
  e.n = d.n;
  e.phi_init = d.phi_init;
  e.log10_rate = d.log10_rate;
  e.phi_grid = step_grid(0.80, 0.86, d.phi_step, d.phi_offset);
  e.z_grid = step_grid(3.8, 4.6, d.z_step);
  const double phi_length = 0.001 / std::log(1 / 0.9);
  for (int s = 0; s < d.samples; ++s) {
    e.sample_ids.push_back(d.first_id + s);
    e.pressure_at_phi.push_back(correlated_run(
        e.phi_grid, [](double phi) { return std::exp(30 * (phi - 0.84)); }, d.shift, d.scatter,
        phi_length, rng));
    e.pressure_at_z.push_back(correlated_run(
        e.z_grid, [](double z) { return std::exp(5 * (z - 4.2)); }, d.shift, d.scatter, 0.1, rng));
  }
  if (std::isfinite(d.jamming_mean)) {
    std::normal_distribution<double> g(d.jamming_mean, d.jamming_spread);
    for (int s = 0; s < d.samples; ++s) e.jamming_points.push_back(g(rng));
  }
  return e;
}

}  // namespace jam::checks::testing
