#include "stats/sample_ids.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "sim/io/hdf5_file.hpp"
#include "sim/io/whole_number.hpp"

namespace jam::stats {

std::vector<std::int64_t> read_sample_ids(const h5::File& f, const std::string& group) {
  std::vector<std::int64_t> ids;
  for (double id : f.read_dataset(group + "/sample_ids")) {
    const auto whole = whole_number(id, -kMaxExactWhole, kMaxExactWhole);
    if (!whole) {
      throw std::runtime_error(fmt::format(
          "{}: dataset '{}/sample_ids' holds {}, not a sample number", f.path(), group, id));
    }
    ids.push_back(*whole);
  }
  return ids;
}

}  // namespace jam::stats
