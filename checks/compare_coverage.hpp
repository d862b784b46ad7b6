#pragma once
// Which runs the compare check judges, and over which range (checks/compare_check.hpp).
// `jam stats` averages an ensemble only where every run has data, so one run that stopped
// early (a crash, another code's shorter output) would shrink every comparison to its own end
// and let a difference beyond it pass unseen. Compare therefore reads the tables stats.h5 keeps
// over the grid any run reaches (stats/run_coverage.hpp, NaN beyond a run's end) and:
//   - asks REF's range: --phi-min/--phi-max, else REF's scaling-fit window, else from past
//     both start transients up to REF's end, where half of REF's runs reach;
//   - leaves out, by name, a run of either side that ends short of that range: before 90% of
//     the part of it its own side reaches (the rest then cover the range up to the shortest of
//     them, never down to the short run's end);
//   - judges a range much narrower than asked (less than kNarrowShare of it) never a pass;
//   - flags output far coarser than the grid (a run's median spacing above kCoarseFactor grid
//     steps): such a run is interpolated linearly across the start's transient, so it is
//     judged only from one of its output steps past the transient.
#include <cmath>
#include <string>
#include <vector>

#include "checks/pooled_verdict.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

constexpr double kCoverShare = 0.9;    // of the range its side reaches, a kept run covers
constexpr double kNarrowShare = 0.5;   // of the range asked, a pass needs judged
constexpr double kCoarseFactor = 4.0;  // output spacing over grid step beyond which it is coarse

/// e with the widest tables stats.h5 holds (its coverage) in place of the common ones.
EnsembleTables widened(const EnsembleTables& e);

/// Where half of e's runs reach in the variable (phi, or Z when at_z): the median over its runs
/// of the last grid value with data (NaN with no run).
double typical_end(const EnsembleTables& e, bool at_z);

/// The runs of one side as judged.
struct CoveringRuns {
  EnsembleTables tables;  // widened, without the rows left out (in the variable's table)
  std::vector<std::string> left_out;  // "sample 0 (data to phi 0.815)"
};

/// Leaves out of e (widened) the runs whose data end before lo + kCoverShare (reach - lo),
/// reach = min(hi, typical_end(e)): at constant phi from the phi table, at constant Z from the Z
/// table.
CoveringRuns covering_runs(const EnsembleTables& e, bool at_z, double lo, double hi);

/// The largest output spacing in packing of e's runs whose spacing exceeds kCoarseFactor
/// times e's constant-phi grid step (NaN: none, or not known).
double coarse_step(const EnsembleTables& e);

/// Output far coarser than the grid in either side (coarse_step): the range and the pointwise
/// rule start one output step past the start's transient (kStartTransient past from_phi, in
/// the range's variable), as does *floor (where the regions start); v gets the value
/// coarse_step. Returns the words for the reason ("" when no run is coarse).
std::string past_coarse_output(PoolRange& range, double* floor, bool at_z,
                               const EnsembleTables& dir, const EnsembleTables& ref,
                               double from_phi, Verdict& v);

/// The runs left out of a comparison over `range`, in words ("" when none).
std::string left_out_words(const CoveringRuns& dir, const CoveringRuns& ref,
                           const PoolRange& range);

/// A pass judged over [judged_min, judged_max] of the range asked [asked_min, asked_max]
/// becomes inconclusive when it covers less than kNarrowShare of it, saying both ranges. Other
/// outcomes stand: a difference beyond the margin found on part of the range is one.
void never_pass_narrow(Verdict& v, double asked_min, double asked_max);

}  // namespace jam::checks
