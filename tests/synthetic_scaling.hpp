#pragma once
// Synthetic constant-phi averages drawn from a known scaling function (the paper's Eq. (1)),
// for the scaling fit's tests: a cubic ln f, sample-to-sample noise correlated along each run.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "stats/scaling_fit.hpp"

namespace jam::test {

using jam::stats::FitEnsemble;

struct Truth {
  double phi_j = 0.8415, rate_exponent = 0.30, inv_znu = 0.27;
  std::vector<double> c = {0.0, 1.5, -0.3, 0.05};  // ln f(x), cubic
  double beta() const { return (1 - rate_exponent) / inv_znu; }
  double y() const { return rate_exponent / inv_znu; }
  double pressure(double phi, double rate) const {
    const double x = (phi - phi_j) / std::pow(rate, inv_znu);
    double ln_f = 0.0;
    for (std::size_t n = c.size(); n-- > 0;) ln_f = ln_f * x + c[n];
    return std::pow(rate, rate_exponent) * std::exp(ln_f);
  }
};

// Rates 1e-5 .. 10^-6.5, 10 samples sharing ids across rates, packings every 0.001. Each
// sample's pressure is the truth times exp(eps), eps an AR(1) process along phi with
// neighbour correlation 0.95 and 10% amplitude (the scatter seen at these sizes).
inline std::vector<FitEnsemble> synthetic(const Truth& t, std::uint64_t seed, int samples = 10,
                                   double phi_lo = 0.78, double phi_hi = 0.90,
                                   double sigma = 0.10,
                                   std::vector<double> rates = {-5.0, -5.5, -6.0, -6.5}) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const double rho = 0.95;
  std::vector<FitEnsemble> ens;
  for (double lr : rates) {
    FitEnsemble e;
    e.rate = std::pow(10.0, lr);
    for (double phi = phi_lo; phi <= phi_hi + 1e-9; phi += 0.001) e.phi.push_back(phi);
    for (int s = 0; s < samples; ++s) {
      e.sample_ids.push_back(s);
      std::vector<double> row;
      double eps = sigma * g(rng);
      for (double phi : e.phi) {
        row.push_back(t.pressure(phi, e.rate) * std::exp(eps));
        eps = rho * eps + sigma * std::sqrt(1 - rho * rho) * g(rng);
      }
      e.pressure.push_back(std::move(row));
    }
    ens.push_back(std::move(e));
  }
  return ens;
}

/// Multiplies every pressure by exp(a (phi - phi_J)) = exp(a x rate^(1/z nu)): an analytic
/// correction to scaling, which moves fits at fast rates more than at slow ones.
inline void plant_correction(std::vector<FitEnsemble>& data, double a, double phi_j) {
  for (auto& e : data)
    for (auto& row : e.pressure)
      for (std::size_t i = 0; i < row.size(); ++i) row[i] *= std::exp(a * (e.phi[i] - phi_j));
}

}  // namespace jam::test
