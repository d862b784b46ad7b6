#pragma once
// The few helpers hdf5_file.cpp (writing, opening) and hdf5_read.cpp (checked reading) share:
// an HDF5 failure turned into std::runtime_error naming what failed.
#include <hdf5.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace jam::h5::detail {

/// "4000" or "2x3": the extent of a simple dataspace, for errors.
inline std::string extent_words(const std::vector<hsize_t>& dims) {
  std::string s;
  for (std::size_t k = 0; k < dims.size(); ++k) {
    if (k > 0) s += 'x';
    s += std::to_string(dims[k]);
  }
  return s;
}

inline hid_t check(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error(what);
  return id;
}

inline void check_status(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error(what);
}

}  // namespace jam::h5::detail
