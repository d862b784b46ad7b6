#include "checks/regions.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace jam::checks {

JammingReference jamming_reference(const StatsData& d, std::optional<double> given) {
  if (given) return {*given, fmt::format("phi_J {:.5f} as given (--phi-j or [regions])", *given)};
  if (d.fit_phi_j && std::isfinite(*d.fit_phi_j))
    return {*d.fit_phi_j, fmt::format("the scaling fit's phi_J {:.5f}", *d.fit_phi_j)};
  // The largest size that looked for jamming points: its phi_Ji scatter least.
  std::int64_t largest = 0;
  for (const auto& e : d.ensembles)
    for (double x : e.jamming_points)
      if (std::isfinite(x)) largest = std::max(largest, e.n);
  double sum = 0;
  int count = 0;
  for (const auto& e : d.ensembles)
    if (e.n == largest)
      for (double x : e.jamming_points)
        if (std::isfinite(x)) sum += x, ++count;
  if (count == 0) return {};
  const double mean = sum / count;
  return {mean, fmt::format("<phi_Ji> {:.5f} of N = {} ({} jamming points)", mean, largest, count)};
}

std::string Region::words() const {
  return fmt::format("{} jamming, phi in [{:.4f}, {:.4f}]", name, min, max);
}

std::vector<Region> regions_around(const JammingReference& j, const RegionOffsets& o) {
  if (!j.known()) return {};
  return {{"below", j.phi_j - o.far, j.phi_j - o.near},
          {"at", j.phi_j - o.near, j.phi_j + o.near},
          {"above", j.phi_j + o.near, j.phi_j + o.far}};
}

}  // namespace jam::checks
