#pragma once
// Where along the compression a pressure verdict judges. A pooled verdict over a wide range
// weighs the points as a fit does, so where the weights lie decides what it sees: at the slow
// rates of the paper's 2D study 80% of the weight lay within 0.009 of phi_J and above it, and
// a size effect of -15% below jamming passed unseen. So every pressure check (finite_size,
// phi_init, chain, compare, sample_pairs) judges, beside its pooled verdict, three regions
// fixed before the data relative to the campaign's phi_J, stated once (the defaults here,
// `--region-near`, `--region-far`):
//   below  [phi_J - far,  phi_J - near]
//   at     [phi_J - near, phi_J + near]
//   above  [phi_J + near, phi_J + far]
// with near = 0.004 and far = 0.012 by default: the "at" region spans about the sample spread
// of phi_Ji at N ~ 10^3-10^4 (0.0003-0.003) plus the fit's error of phi_J, and the outer
// regions the scaling fit's usual window (phi_J +- 0.01) outside it.
//
// phi_J comes, in order, from --phi-j (the user's), the constant-phi scaling fit in stats.h5,
// the mean jamming point <phi_Ji> of the largest size that looked for them, or the packing
// where the constant-phi <Z> of the largest size at the slowest rate crosses isostaticity,
// Z_iso = 2 D (a two-rate design has no fit, and runs seldom look for jamming points; the
// contacts are always stored). <Z> counts rattlers, so it crosses 2 D at or a little above the
// packing where the rigid backbone does: the regions are placed by the data, before any
// verdict, and say where they come from. Without any, no region around jamming is placed, and
// a pooled verdict over the whole compression says so (its values' whole_compression, the
// table's and the report's line for the check).
//
// A campaign that states a range ([question] phi_min, phi_max, campaign/campaign_file.hpp)
// has that range judged as one more region, "asked", whether or not phi_J is known.
//
// Every region verdict is one more comparison for the check's detection level (Bonferroni over
// comparisons and regions), so a check's false-alarm rate stays alpha; a pass is an
// intersection of two one-sided tests and needs no share.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "checks/stats_data.hpp"

namespace jam::checks {

/// Where the regions lie: the offsets of those around phi_J, and the range asked.
struct RegionOffsets {
  RegionOffsets() = default;
  RegionOffsets(double near_, double far_) : near(near_), far(far_) {}  // {near, far}
  double near = 0.004, far = 0.012;
  // The range the campaign asks about ([question] phi_min, phi_max, or --phi-min/--phi-max
  // replacing it): the region "asked". Absent: none.
  std::optional<double> asked_min, asked_max;
  std::string asked_from = "[question] phi_min, phi_max";  // where it was stated
  bool asks() const { return asked_min.has_value() && asked_max.has_value(); }
};

/// The packing the regions are placed around, and where it comes from (words for a reason).
struct JammingReference {
  double phi_j = NAN;  // NaN: none known
  // e.g. "the scaling fit's phi_J"; when none is known, why not ("no scaling fit, no jamming
  // points, and <Z> of N = 512 at rate 1e-5 stays below 2D = 4 (at most 3.1)").
  std::string from;
  bool known() const { return std::isfinite(phi_j); }
};
JammingReference jamming_reference(const StatsData& d, std::optional<double> given);

/// Where <Z> first rises through z_iso along e's grid, between the two points that bracket it
/// (linear); NaN when it never does (or e stores no <Z>).
double z_crossing(const EnsembleTables& e, double z_iso);

/// One region of the compression, in packing.
struct Region {
  std::string name;  // "below", "at", "above", "asked"
  double min = 0, max = 0;
  std::string from;           // "asked": where the range was stated
  std::string words() const;  // "below jamming, phi in [0.8289, 0.8369]"
  // What a verdict's case name adds: "below jamming", "range asked".
  std::string case_words() const;
};

/// The region asked (when o states one), then the three around phi_J (when it is known).
std::vector<Region> regions_around(const JammingReference& j, const RegionOffsets& o);

/// The verdicts one comparison makes: 1 pooled + one per region (for a check's Bonferroni
/// share).
inline std::size_t verdicts_per_comparison(const JammingReference& j, const RegionOffsets& o) {
  return 1 + regions_around(j, o).size();
}

}  // namespace jam::checks
