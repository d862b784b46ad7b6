#pragma once
// The rules of reference/schema/stats.toml (embedded at the build), applied to an open
// stats.h5: the one definition of what a stats.h5 holds, which python/jamio/stats_schema.py
// applies too (tests/test_stats_schema.py feeds both the same corpus). Every C++ reader of a
// stats.h5 (the checks' read_stats, `jam stats --refit`, `jam validate --stats`) checks it once
// on opening, after its checksum. The messages name the object, the field and its value:
//   <file>: attribute 'dim' is 7, not 2 or 3
//   <file>: dataset 'ensembles/e/constant_phi/pressure_samples' has 23 values, expected 20
//     (S x M = 4 x 5)
//   <file>: dataset 'ensembles/e/constant_phi/packing_fraction' holds nan, not a finite number
#include <cstddef>
#include <string>
#include <vector>

#include "sim/io/hdf5_file.hpp"

namespace jam::stats {

/// The schema versions this jam reads, and the one it writes (root attribute
/// `schema_version`; a file without it is schema 1).
const std::vector<int>& stats_schema_versions();
int current_stats_schema_version();

/// Throws std::runtime_error with one line naming f's path and the first group, attribute or
/// dataset that breaks its rule.
void check_stats_schema(const h5::File& f);

/// What `jam validate --stats` says of a stats.h5 that passes.
struct StatsFileSummary {
  int schema_version = 1;
  std::string campaign;
  std::size_t ensembles = 0;
};

/// Opens the stats.h5 at `path` and checks it as every reader does (its checksum, then the
/// schema); throws one line starting with the path when it fails.
StatsFileSummary check_stats_file(const std::string& path);

}  // namespace jam::stats
