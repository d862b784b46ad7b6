#include "stats/run_coverage.hpp"

#include <algorithm>
#include <cmath>

namespace jam::stats {

double median_spacing(const std::vector<double>& x) {
  std::vector<double> steps;
  for (std::size_t k = 1; k < x.size(); ++k)
    if (x[k] > x[k - 1]) steps.push_back(x[k] - x[k - 1]);
  if (steps.empty()) return NAN;
  const auto middle = steps.begin() + static_cast<long>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  return *middle;
}

RunCoverage run_coverage(const std::vector<RunCurves>& runs, double phi_step, double z_step,
                         bool no_rattlers, const GridAverage& common_phi,
                         const std::optional<GridAverage>& common_z) {
  RunCoverage c;
  for (const auto& r : runs) {
    c.sample_ids.push_back(r.sample);
    c.phi_last.push_back(r.phi.back());
    c.output_step.push_back(median_spacing(r.phi));
  }
  // The wider tables only where some run reaches past the common grid: equal ends (every
  // planned campaign of jam's) store nothing more.
  GridAverage phi = average_at_constant_phi(runs, phi_step, Span::any_sample);
  if (phi.grid.size() > common_phi.grid.size()) c.constant_phi = std::move(phi);
  if (common_z) {
    GridAverage z = average_at_constant_z(runs, z_step, no_rattlers, Span::any_sample);
    if (z.grid.size() > common_z->grid.size()) c.constant_z = std::move(z);
  }
  return c;
}

}  // namespace jam::stats
