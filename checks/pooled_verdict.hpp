#pragma once
// The verdict of every pressure check (finite_size, phi_init, zeta, chain): two run sets
// judged on one aggregate over a stated range, the inverse-variance weighted mean relative
// difference D (relative_difference.hpp, compare_weighted), plus the pointwise rule that fails
// a point whose simultaneous band lies wholly beyond the margin. Why pooled: neighbouring grid
// points come from the same runs, so the maximum over hundreds of them at a Bonferroni alpha
// (the former statistic) spends its power on the noisiest point; D is the shift a
// least-squares fit over the range sees, and its error is that of the whole range.
//
// The range is part of the verdict: its edges, why it is that range, and where the weights lie
// (their mean and the span holding the central 80% of them) are in the reason and the values.
#include <functional>
#include <optional>
#include <string>

#include "checks/checks.hpp"
#include "checks/regions.hpp"
#include "checks/relative_difference.hpp"
#include "checks/stats_data.hpp"

namespace jam::checks {

struct PoolRange {
  std::string variable = "phi";  // the grid: "phi" or "Z"
  double min = -HUGE_VAL, max = HUGE_VAL;
  std::string why;  // e.g. "the scaling fit's window (phi_J +- 0.01)"
  // The pointwise rule judges no point below this: the start's transient (kStartTransient past
  // where the compression takes over, margin.hpp), where a relaxed start's pressure is still
  // building and the first points differ by tens of percent between sizes that agree later.
  double pointwise_from = -HUGE_VAL;
  // The whole compressed range, for want of anything narrower (no fit window, no range given):
  // with no region beside it, the verdict says so (values whole_compression = 1, and in its
  // reason why no region could be placed: no_regions_because).
  bool whole = false;
  std::string no_regions_because;
};

/// The packing range a check at constant phi pools over: --phi-min/--phi-max when given, else
/// the campaign's scaling-fit window, else (when `need_fit` is false) everything past the
/// starts' transients; never below `compressed` (where the compression, not the start, sets
/// both sets' pressure). nullopt, with *why_not, when need_fit and there is no fit.
std::optional<PoolRange> phi_range(const StatsData& d, const CheckOptions& o, double compressed,
                                   bool need_fit, std::string* why_not);

/// The same at constant Z: the Z values whose mean packing lies in the constant-Z fit's
/// window (else the constant-phi fit's) in both sets, never below `compressed_z`.
PoolRange z_range(const StatsData& d, const CheckOptions& o, const EnsembleTables& a,
                  const EnsembleTables& b, double compressed_z);

/// The rows of `al` whose grid value lies in [lo, hi].
Aligned cut(const Aligned& al, double lo, double hi);

/// The Z range whose mean packing lies in [phi_lo, phi_hi] in both sets (all of Z when a set
/// stores no mean packing): [+inf, -inf] when there is none.
std::pair<double, double> z_span(const EnsembleTables& a, const EnsembleTables& b, double phi_lo,
                                 double phi_hi);

/// Where the pointwise rule may start for a comparison of a and b: kStartTransient (margin.hpp)
/// past the packing `compressed_phi` where both are compressed, or at constant Z the Z whose
/// mean packing is there.
double pointwise_start(bool at_z, const EnsembleTables& a, const EnsembleTables& b,
                       double compressed_phi);

/// The ranges of `regions` for a comparison of a and b: in packing, or at constant Z the Z
/// whose mean packing lies in each (z_span); never below `compressed` (in the grid's
/// variable); each says in its why which region and where phi_J comes from.
std::vector<PoolRange> region_ranges(const std::vector<Region>& regions, const JammingReference& j,
                                     bool at_z, const EnsembleTables& a, const EnsembleTables& b,
                                     double compressed, double pointwise_from);

/// One comparison judged pooled over `pooled` and in each region: the verdict `base` (check,
/// case name and values set) copied into one verdict per range, region "pooled", then those
/// of `regions` (their variable as pooled's; the region's name in PoolRange::why's place is
/// taken from `names`). `al`: the two sets over everything compared. A region with fewer than
/// 2 common points is inconclusive and says which range the data cover.
std::vector<Verdict> judge_by_region(const Verdict& base, const Aligned& al,
                                     const PoolRange& pooled, const std::vector<Region>& names,
                                     const std::vector<PoolRange>& regions, Levels levels,
                                     double margin, int permutations, std::uint64_t seed = 3,
                                     RelativeTo relative_to = RelativeTo::mean);

/// The same where each range's data come from `data` (e.g. grids matched within the range
/// only): called once per range with the verdict it is for (region set), which it may add
/// values to.
using RangeData = std::function<Aligned(const PoolRange&, Verdict&)>;
std::vector<Verdict> judge_by_region(const Verdict& base, const RangeData& data,
                                     const PoolRange& pooled, const std::vector<Region>& names,
                                     const std::vector<PoolRange>& regions, Levels levels,
                                     double margin, int permutations, std::uint64_t seed = 3,
                                     RelativeTo relative_to = RelativeTo::mean);

/// Marks v, a pooled verdict over `pooled`, when it pools the whole compression with no
/// region judged beside it: values whole_compression = 1, and its reason says why (no range
/// asked, and pooled.no_regions_because).
void say_if_whole(Verdict& v, const PoolRange& pooled, bool regions_judged);

/// Judges v on the two run sets of `al` (cut to the range already): D over the range at
/// `levels`, the pointwise rule at levels.detect. Sets statistic_name, the range and weight
/// values (range_min, range_max, weighted_at, weight_from, weight_to,
/// pointwise_excluded_above) and the curves (grid, delta, sigma, weight). `relative_to`:
/// Delta p/p relative to the mean of both sets, or to set B (a reference). Throws
/// std::invalid_argument as compare_weighted does.
void judge_pooled(Verdict& v, const Aligned& al, const PoolRange& range, Levels levels,
                  double margin, int permutations, std::uint64_t seed = 3,
                  RelativeTo relative_to = RelativeTo::mean);

}  // namespace jam::checks
