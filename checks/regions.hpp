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
// or the mean jamming point <phi_Ji> of the largest size that looked for them; without any,
// no region is placed and the pooled verdict says in its first words that it pools the whole
// compressed range.
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

struct RegionOffsets {
  double near = 0.004, far = 0.012;
};

/// The packing the regions are placed around, and where it comes from (words for a reason).
struct JammingReference {
  double phi_j = NAN;  // NaN: none known
  std::string from;    // e.g. "the scaling fit's phi_J"
  bool known() const { return std::isfinite(phi_j); }
};
JammingReference jamming_reference(const StatsData& d, std::optional<double> given);

/// One region of the compression, in packing.
struct Region {
  std::string name;  // "below", "at", "above"
  double min = 0, max = 0;
  std::string words() const;  // "below jamming, phi in [0.8289, 0.8369]"
};

/// The three regions around phi_J (empty when phi_J is unknown).
std::vector<Region> regions_around(const JammingReference& j, const RegionOffsets& o);

/// The verdicts one comparison makes: 1 pooled + one per region (for a check's Bonferroni
/// share).
inline std::size_t verdicts_per_comparison(const JammingReference& j) {
  return j.known() ? 4 : 1;
}

}  // namespace jam::checks
