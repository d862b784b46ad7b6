#pragma once
// Ensemble averages on a common grid (the paper's main text and supplement):
//  - at constant packing phi: p(phi) and Z(phi) of each run, linearly interpolated between its
//    output points onto phi_k = k * phi_step, then averaged over samples;
//  - at constant contact number Z: phi(Z) and p(Z) of each run at the first packing where its
//    Z reaches Z_k (linear interpolation within that output interval), then averaged. Z is over
//    all particles as in the paper, or with rattlers removed when the runs stored it.
// Each grid spans only the range every sample covers. The per-sample tables are kept: they are
// what jackknife errors, sample-pair checks and the fits resample. Span::any_sample extends a
// grid up to where the longest sample ends, NaN in the rows of the samples that end before: the
// compare check judges REF's range there whatever one short run covers (stats/run_coverage.hpp).
#include <cstddef>
#include <string>
#include <vector>

#include "stats/run_curves.hpp"
#include "stats/sample_average.hpp"

namespace jam::stats {

struct GridAverage {
  std::string grid_name;  // "packing_fraction" or "contacts_per_particle"
  std::vector<double> grid;
  std::vector<std::int64_t> sample_ids;
  // Observables on the grid: name -> [sample][point] and its mean and standard error.
  std::vector<std::string> names;
  std::vector<std::vector<std::vector<double>>> tables;
  std::vector<std::vector<SampleMean>> means;

  const std::vector<std::vector<double>>& table(const std::string& name) const;
  const std::vector<SampleMean>& mean(const std::string& name) const;
};

/// Computes a.means from a.tables.
void finalize(GridAverage& a);

/// Linear interpolation of y(x) at x0 for increasing x; NaN outside [x.front(), x.back()].
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double x0);

/// How far up a grid reaches: where every sample ends (the averages), or where the longest
/// one ends (NaN beyond a sample's own end; its means are NaN there).
enum class Span { every_sample, any_sample };

/// Averages at constant phi on phi_k = k * phi_step.
GridAverage average_at_constant_phi(const std::vector<RunCurves>& samples, double phi_step,
                                    Span span = Span::every_sample);

/// Averages at constant Z on Z_k = k * z_step (rattlers removed when no_rattlers).
GridAverage average_at_constant_z(const std::vector<RunCurves>& samples, double z_step,
                                  bool no_rattlers, Span span = Span::every_sample);

}  // namespace jam::stats
