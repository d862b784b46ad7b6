#pragma once
// What each run of an ensemble covers, for judging two campaigns over a stated range (the
// compare check, checks/compare_coverage.hpp) rather than over whatever the shortest run
// reaches: the ensemble's averages span only where every run has data (averages.hpp), so one
// run that stopped early would otherwise shrink every comparison to its own end.
//   - each run's last output packing and the median spacing of its output packings (output far
//     coarser than the grid is linearly interpolated across the start's transient);
//   - the ensemble's tables again over the grid any run reaches (Span::any_sample, NaN beyond
//     a run's end), kept only where that grid is longer than the common one.
// stats.h5 stores it as ensembles/<name>/coverage/ (reference/schema.md).
#include <cstdint>
#include <optional>
#include <vector>

#include "stats/averages.hpp"
#include "stats/run_curves.hpp"

namespace jam::stats {

struct RunCoverage {
  // One entry per run, in the order of the ensemble's constant_phi sample_ids.
  std::vector<std::int64_t> sample_ids;
  std::vector<double> phi_last;     // the run's last output packing
  std::vector<double> output_step;  // the median spacing of its output packings (NaN: < 2)
  // The averages over the grid any run reaches, when longer than the common grid's.
  std::optional<GridAverage> constant_phi, constant_z;
};

/// The coverage of an ensemble's runs; `common_phi` and `common_z` are its averages over the
/// grid every run covers (constant_z absent when there is none), made with phi_step, z_step and
/// no_rattlers.
RunCoverage run_coverage(const std::vector<RunCurves>& runs, double phi_step, double z_step,
                         bool no_rattlers, const GridAverage& common_phi,
                         const std::optional<GridAverage>& common_z);

/// The median of the positive spacings of an increasing sequence (NaN with fewer than two).
double median_spacing(const std::vector<double>& x);

}  // namespace jam::stats
