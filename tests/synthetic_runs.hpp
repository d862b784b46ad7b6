#pragma once
// Synthetic run sets for the statistical checks' tests: S runs of
// p(phi) = exp(30 (phi - 0.84)) * (1 + shift) * exp(eps), eps an AR(1) process along the grid
// (neighbour correlation 0.9, 10% amplitude unless given), like the scatter of real runs.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "checks/stats_data.hpp"

namespace jam::checks::testing {

inline std::vector<std::vector<double>> runs(int samples, double shift, std::mt19937_64& rng,
                                             std::size_t points = 60, double amplitude = 0.1) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> t;
  for (int s = 0; s < samples; ++s) {
    std::vector<double> row;
    double eps = amplitude * g(rng);
    for (std::size_t k = 0; k < points; ++k) {
      const double phi = 0.80 + 0.001 * static_cast<double>(k);
      row.push_back(std::exp(30 * (phi - 0.84)) * (1 + shift) * std::exp(eps));
      eps = 0.9 * eps + amplitude * std::sqrt(1 - 0.81) * g(rng);
    }
    t.push_back(std::move(row));
  }
  return t;
}

/// An ensemble on the grid 0.800, 0.801, ... with samples numbered first_id, first_id + 1, ...
inline EnsembleTables ensemble(std::int64_t n, double phi_init, double log10_rate,
                               std::vector<std::vector<double>> p, std::uint32_t first_id = 0) {
  EnsembleTables e;
  e.n = n;
  e.phi_init = phi_init;
  e.log10_rate = log10_rate;
  for (std::size_t k = 0; k < p.front().size(); ++k) e.phi_grid.push_back(0.80 + 0.001 * k);
  for (std::size_t s = 0; s < p.size(); ++s)
    e.sample_ids.push_back(first_id + static_cast<std::int64_t>(s));
  e.pressure_at_phi = std::move(p);
  return e;
}

}  // namespace jam::checks::testing
