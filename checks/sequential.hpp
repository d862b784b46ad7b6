#pragma once
// Looking again after more samples (`jam campaign run --until-decided`): repeated
// confidence intervals with Bonferroni alpha spending over the looks. Look k (from 1) judges
// every still-undecided verdict at
//   alpha_k = alpha / (k (k + 1)),   sum over k of alpha_k = alpha,
// for its detection and its pass alike, and a verdict decided at a look is final. Whatever the
// number of looks and however the samples added depend on earlier looks, the chance that any
// look falsely fails (or falsely passes) a verdict is at most alpha (the union bound over
// looks); no assumption on the correlation between looks is needed. The first look keeps half
// of alpha, the second a sixth, the third a twelfth. Measured in tests/test_sequential.cpp.
#include <stdexcept>

namespace jam::checks {

inline double look_alpha(double alpha, int look) {
  if (look < 1) throw std::invalid_argument("look_alpha: looks count from 1");
  return alpha / (static_cast<double>(look) * static_cast<double>(look + 1));
}

/// The samples per set the next look of an undecided verdict asks for: its samples_needed,
/// at least 1.5 times and at most twice the present count (so that a poor estimate costs at
/// most one doubling, and a look always adds enough to move the bounds).
inline long next_samples(long present, double samples_needed) {
  const long lo = present + (present + 1) / 2, hi = 2 * present;
  if (!(samples_needed == samples_needed)) return hi;  // NaN: no estimate
  const double want = samples_needed;
  return want <= static_cast<double>(lo)   ? lo
         : want >= static_cast<double>(hi) ? hi
                                           : static_cast<long>(want + 0.999999);
}

/// The same for one set of a verdict whose estimate names each set's samples (the cheapest
/// split, window_scatter.hpp): a set that has its share already gets none.
inline long next_samples_of_set(long present, double samples_needed) {
  if (samples_needed == samples_needed && samples_needed <= static_cast<double>(present))
    return present;
  return next_samples(present, samples_needed);
}

}  // namespace jam::checks
