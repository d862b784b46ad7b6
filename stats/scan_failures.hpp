#pragma once
// The failed rows of a scaling-fit scan, folded for a terminal: a small campaign's scan fails
// the same way in every row (two rates: "a scaling fit needs at least 3"), and one line per
// row buried the averages above it. stats.h5 keeps every row and its reason (fit/scan,
// attribute `failures`); only the printed summary folds them.
#include <string>
#include <vector>

#include "stats/campaign_stats.hpp"

namespace jam::stats {

/// One kind of failure: the reason of its first row and how many rows failed so. Rows whose
/// reasons differ only in their numbers (the rate_max or window they name) are one kind.
struct ScanFailureKind {
  std::string reason;  // the first row's reason, without its leading "fit: "
  std::size_t rows = 0;
  bool numbers_differ = false;  // some of its rows name other numbers than the first
};

/// The kinds of the scan's failed rows, in the order first met.
std::vector<ScanFailureKind> scan_failure_kinds(const FitScan& scan);

/// "6 rows: reason | 2 rows, e.g.: reason" (", e.g." where the rows' numbers differ).
std::string scan_failure_words(const FitScan& scan);

}  // namespace jam::stats
