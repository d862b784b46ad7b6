#pragma once
// The sample numbers of a stats.h5 table, `<group>/sample_ids` (reference/schema.md): stored as
// doubles, read back as integers only when each is a whole number, since converting a fraction
// truncates it without a word and converting NaN or a value beyond int64 is undefined. One
// reader for `jam stats --refit` (stats_reader.cpp) and the checks (checks/stats_data.cpp).

#include <cstdint>
#include <string>
#include <vector>

namespace jam::h5 {
class File;
}

namespace jam::stats {

/// `<group>/sample_ids` of f, in order; throws naming the file, the dataset and the value when
/// one is not a sample number.
std::vector<std::int64_t> read_sample_ids(const h5::File& f, const std::string& group);

}  // namespace jam::stats
