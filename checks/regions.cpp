#include "checks/regions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>

namespace jam::checks {
namespace {

/// phi_J where <Z> of the largest size at its slowest rate crosses 2 D; when it does not, an
/// unknown reference whose words say why (and what <Z> did).
JammingReference isostatic_reference(const StatsData& d) {
  // Largest size, then slowest rate, then lowest phi_init: the least noisy crossing first. A
  // chained slow rate may start above Z_iso: then the next in that order.
  std::vector<const EnsembleTables*> order;
  for (const auto& e : d.ensembles)
    if (!e.z_at_phi.empty()) order.push_back(&e);
  std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) {
    return std::tuple(-a->n, a->log10_rate, a->phi_init) <
           std::tuple(-b->n, b->log10_rate, b->phi_init);
  });
  const std::string none = "no phi_J: no scaling fit, no jamming points";
  if (order.empty()) return {NAN, none + ", and no <Z> at constant phi in stats.h5"};
  const double z_iso = 2.0 * d.dim;
  auto whose = [](const EnsembleTables& e) {
    return fmt::format("<Z> of N = {} at rate 1e{:g}", e.n, e.log10_rate);
  };
  for (const EnsembleTables* e : order) {
    const double phi = z_crossing(*e, z_iso);
    if (std::isfinite(phi))
      return {phi,
              fmt::format("the packing {:.5f} where {} crosses 2D = {:g}", phi, whose(*e), z_iso)};
  }
  const EnsembleTables* chosen = order.front();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double z : chosen->z_at_phi)
    if (std::isfinite(z)) lo = std::min(lo, z), hi = std::max(hi, z);
  const std::string what =
      !(lo <= hi)  ? "has no finite value"
      : hi < z_iso ? fmt::format("stays below 2D = {:g} (at most {:.3g})", z_iso, hi)
      : lo >= z_iso
          ? fmt::format("lies above 2D = {:g} from the start (at least {:.3g})", z_iso, lo)
          : fmt::format("never rises through 2D = {:g} between two points", z_iso);
  return {NAN, fmt::format("{}, and {} {} within the data{}", none, whose(*chosen), what,
                           order.size() > 1 ? " (nor does that of any other ensemble)" : "")};
}

}  // namespace

double z_crossing(const EnsembleTables& e, double z_iso) {
  const std::size_t m = std::min(e.z_at_phi.size(), e.phi_grid.size());
  for (std::size_t k = 1; k < m; ++k) {
    const double z0 = e.z_at_phi[k - 1], z1 = e.z_at_phi[k];
    if (!(std::isfinite(z0) && std::isfinite(z1))) continue;
    if (z0 < z_iso && z1 >= z_iso) {
      const double t = (z_iso - z0) / (z1 - z0);
      return e.phi_grid[k - 1] + t * (e.phi_grid[k] - e.phi_grid[k - 1]);
    }
  }
  return NAN;
}

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
  if (count == 0) return isostatic_reference(d);
  const double mean = sum / count;
  return {mean, fmt::format("<phi_Ji> {:.5f} of N = {} ({} jamming points)", mean, largest, count)};
}

std::string Region::words() const {
  if (name == "asked")
    return fmt::format("the range asked ({}), phi in [{:.4f}, {:.4f}]", from, min, max);
  return fmt::format("{} jamming, phi in [{:.4f}, {:.4f}]", name, min, max);
}

std::string Region::case_words() const {
  return name == "asked" ? std::string("range asked") : name + " jamming";
}

std::vector<Region> regions_around(const JammingReference& j, const RegionOffsets& o) {
  std::vector<Region> out;
  if (o.asks()) out.push_back({"asked", *o.asked_min, *o.asked_max, o.asked_from});
  if (!j.known()) return out;
  out.push_back({"below", j.phi_j - o.far, j.phi_j - o.near, ""});
  out.push_back({"at", j.phi_j - o.near, j.phi_j + o.near, ""});
  out.push_back({"above", j.phi_j + o.near, j.phi_j + o.far, ""});
  return out;
}

}  // namespace jam::checks
