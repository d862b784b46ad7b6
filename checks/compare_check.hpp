#pragma once
// Two campaigns of the same model compared ensemble by ensemble (`jam check compare DIR
// --against REF`): DIR, e.g. runs of another simulator imported, against REF, the reference
// simulator's campaign, whatever their sample counts, seeds and output grids. Verdicts:
//   compare            Delta p/p = (p_DIR - p_REF) / p_REF at constant phi and at constant Z,
//                      pooled over a stated range (checks/pooled_verdict.hpp);
//   compare_jamming    <phi_Ji> of DIR against REF, when both runs looked for jamming points;
//   compare_fit        the fitted beta and y of each (N, phi_init), relative to REF's;
//   compare_fit_phi_j  the fitted phi_J, a difference in packing.
// The check itself is declared in checks/checks.hpp (a BaselineCheck of the registry); what
// is here is how two grids are brought to common points, for the check and its tests.
#include <cmath>
#include <cstddef>
#include <vector>

#include "checks/stats_data.hpp"

namespace jam::checks {

/// DIR's and REF's tables on the points compared.
struct GridMatch {
  Aligned aligned;                        // a: DIR's rows, b: REF's rows, on `aligned.grid`
  bool interpolated = false;              // DIR's rows interpolated onto REF's grid
  std::size_t shared = 0;                 // grid values both grids have in the range
  double step_dir = NAN, step_ref = NAN;  // each grid's step (the median spacing)
};

/// The grid values both grids share in [min, max] (stats_data.hpp, align: grids of
/// multiples of a step) when there are at least two; else DIR's rows interpolated linearly
/// onto REF's grid values in [min, max] that lie within DIR's grid (never extrapolated; a
/// point next to a NaN of DIR's row is NaN, and left out by the comparison).
GridMatch match_grids(const std::vector<double>& grid_dir,
                      const std::vector<std::vector<double>>& dir,
                      const std::vector<double>& grid_ref,
                      const std::vector<std::vector<double>>& ref, double min, double max);

/// The step of a grid: the median of its spacings (NaN with fewer than two values).
double grid_step(const std::vector<double>& grid);

}  // namespace jam::checks
