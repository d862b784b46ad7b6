#pragma once
// Whether DIR/stats.h5 can be trusted: its content is what `jam stats` wrote (its `checksum`,
// verified by every reader), and it still describes DIR's runs (one definition for `jam check`,
// which refuses a stats.h5 that does not, and `jam pipeline`, which averages again).
//
// stats.h5 records `inputs_checksum`, a digest of what `jam stats DIR` read, taken before it
// read them (so that a run finished meanwhile makes the file out of date, never the other way
// round):
//   - a planned campaign (campaign.toml): its name, dim, phi_step and chained starts, and every
//     planned run (added-samples.toml's too) by name with its run file's content checksum (the
//     file's `checksum` attribute; "absent" while it is not there);
//   - an external campaign (external.toml): its name, dim and phi_step, and every run listed
//     by name with the checksum it was imported with.
// What only steers the judging (margins, regions, expected failures) is not in it: editing
// those leaves stats.h5 current. A directory without runs/ (a stored result whose runs are
// not kept) and one with neither campaign file have nothing to compare with.
#include <string>

#include "sim/io/hdf5_file.hpp"

namespace jam::stats {

/// Throws, in one line naming the file, when f (DIR/stats.h5, open for reading) carries a
/// `checksum` its content does not match: a table changed by hand, a damaged copy. A file
/// written before stats.h5 carried one is read as it is.
void check_stats_checksum(const h5::File& f, const std::string& directory);

/// The digest as stats.h5 stores it (16 hex digits); "" when DIR has no inputs to digest
/// (neither campaign.toml nor external.toml, or no runs/).
std::string inputs_checksum(const std::string& directory);

/// "" when DIR/stats.h5 was computed from DIR's inputs as they are now (or there is nothing to
/// compare it with); otherwise why not, naming the input: "DIR/runs/x.h5 is newer than it".
/// With a recorded digest the digest decides (a file touched but unchanged is not newer in
/// content); a stats.h5 written before it carried one is judged by modification times.
std::string stale_stats_reason(const std::string& directory);

}  // namespace jam::stats
