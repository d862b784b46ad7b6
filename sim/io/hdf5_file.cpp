#include "sim/io/hdf5_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_errors.hpp"
#include "sim/io/output_path.hpp"

namespace jam::h5 {

using detail::check;
using detail::check_status;
using detail::extent_words;

namespace {

// Writing: failures are WriteError (the directory or the disk, not the data).
hid_t check_write(hid_t id, const std::string& what) {
  if (id < 0) throw WriteError(what);
  return id;
}

void check_write_status(herr_t status, const std::string& what) {
  if (status < 0) throw WriteError(what);
}

// HDF5 prints its own error stack by default; errors are reported through exceptions here.
// No library shutdown at exit: after a failed write (full disk) HDF5 1.10 keeps the file in
// its tables and crashes closing it again at exit; every file jam writes is closed (or its
// temporary removed) before then anyway.
struct SilenceHdf5 {
  SilenceHdf5() {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
};
const SilenceHdf5 silence_hdf5;

// Refuses to follow an external link: it names another file, which could be anything (a FIFO
// would block the open for ever) and is no part of what was checked.
herr_t refuse_external_link(const char*, const char*, const char*, const char*, unsigned*, hid_t,
                            void*) {
  return -1;
}

}  // namespace

hid_t local_links(hid_t property_class) {
  // Created once, under the library lock every caller holds; never closed (HDF5 is not shut
  // down at exit either).
  static const hid_t link = H5Pcreate(H5P_LINK_ACCESS), dataset = H5Pcreate(H5P_DATASET_ACCESS),
                     group = H5Pcreate(H5P_GROUP_ACCESS);
  static const bool set = [] {
    for (const hid_t p : {link, dataset, group}) H5Pset_elink_cb(p, refuse_external_link, nullptr);
    return true;
  }();
  (void)set;
  if (property_class == H5P_DATASET_ACCESS) return dataset;
  if (property_class == H5P_GROUP_ACCESS) return group;
  return link;
}

bool values_outside_the_file(hid_t dataset) {
  const Handle plist(H5Dget_create_plist(dataset), H5Pclose);
  if (plist.get() < 0) return true;  // not known to be inside: not read
  return H5Pget_layout(plist.get()) == H5D_VIRTUAL || H5Pget_external_count(plist.get()) != 0;
}

std::vector<hsize_t> extent(hid_t space, const std::string& what) {
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 0 || rank > H5S_MAX_RANK) throw std::runtime_error(what + ": unreadable shape");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space, dims.data(), nullptr) < 0) {
    throw std::runtime_error(what + ": unreadable shape");
  }
  return dims;
}

hsize_t count_values(const std::vector<hsize_t>& dims, const std::string& what) {
  hsize_t count = 1;
  for (const hsize_t d : dims) {
    // A flipped bit in a dimension can make the product wrap round to a small number.
    if (d != 0 && count > std::numeric_limits<hsize_t>::max() / d) {
      throw std::runtime_error(
          fmt::format("{}: an extent of {} values overflows", what, extent_words(dims)));
    }
    count *= d;
  }
  return count;
}

hsize_t values_in(hid_t space, const std::string& what) {
  const H5S_class_t cls = H5Sget_simple_extent_type(space);
  if (cls == H5S_NULL) return 0;
  if (cls == H5S_SCALAR) return 1;
  if (cls != H5S_SIMPLE) throw std::runtime_error(what + ": unreadable shape");
  return count_values(extent(space, what), what);
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = -1;
  }
  return *this;
}

void Handle::reset() {
  if (id_ >= 0 && close_) close_(id_);
  id_ = -1;
}

std::mutex& library_mutex() {
  static std::mutex m;
  return m;
}

void File::close() {
  const hid_t id = file_.get();
  if (id >= 0) {
    errno = 0;
    const herr_t flushed = H5Fflush(id, H5F_SCOPE_LOCAL);
    file_.release();
    const herr_t closed = H5Fclose(id);
    if (flushed < 0 || closed < 0) {
      const int error = errno;
      if (lock_.owns_lock()) lock_.unlock();
      throw WriteError(
          fmt::format("cannot write HDF5 file '{}': {}", path_, write_failure(path_, error)));
    }
  }
  if (lock_.owns_lock()) lock_.unlock();
}

File File::create(const std::string& path, hsize_t user_block) {
  std::unique_lock lock(library_mutex());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // per thread in thread-safe HDF5 builds
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  H5Pset_obj_track_times(fcpl.get(), false);
  if (user_block > 0) H5Pset_userblock(fcpl.get(), user_block);
  errno = 0;
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT);
  if (id < 0) {
    throw WriteError(
        fmt::format("cannot create HDF5 file '{}': {}", path, write_failure(path, errno)));
  }
  return File(std::move(lock), Handle(id, H5Fclose), path);
}

File File::open_read(const std::string& path) {
  // stat() never waits; opening a FIFO waits for a writer that may never come.
  check_input_file("HDF5 file", path);
  std::unique_lock lock(library_mutex());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  return File(std::move(lock),
              Handle(check(id, fmt::format("cannot open HDF5 file '{}'", path)), H5Fclose), path);
}

namespace {
void write_scalar_attribute(hid_t file, const std::string& object, const std::string& name,
                            hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(check_write(H5Acreate_by_name(file, object.c_str(), name.c_str(), type, space.get(),
                                            H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                          "cannot create attribute " + name),
              H5Aclose);
  check_write_status(H5Awrite(attr.get(), type, value), "cannot write attribute " + name);
}
}  // namespace

void File::write_attribute(const std::string& name, double value, const std::string& object) {
  write_scalar_attribute(id(), object, name, H5T_NATIVE_DOUBLE, &value);
}

void File::write_attribute(const std::string& name, std::int64_t value, const std::string& object) {
  write_scalar_attribute(id(), object, name, H5T_NATIVE_INT64, &value);
}

void File::write_attribute(const std::string& name, const std::string& value,
                           const std::string& object) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), value.empty() ? 1 : value.size());
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  write_scalar_attribute(id(), object, name, type.get(), value.c_str());
}

void File::create_group(const std::string& path) {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  H5Pset_obj_track_times(gcpl.get(), false);
  Handle group(check_write(H5Gcreate2(id(), path.c_str(), lcpl.get(), gcpl.get(), H5P_DEFAULT),
                           "cannot create group " + path),
               H5Gclose);
}

namespace {
void write_array(hid_t file, const std::string& name, hid_t file_type, hid_t memory_type,
                 const void* data, const std::vector<hsize_t>& dims) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl.get(), false);
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle set(check_write(H5Dcreate2(file, name.c_str(), file_type, space.get(), lcpl.get(),
                                    dcpl.get(), H5P_DEFAULT),
                         "cannot create dataset " + name),
             H5Dclose);
  check_write_status(H5Dwrite(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
                     "cannot write dataset " + name);
}

}  // namespace

void File::write_dataset(const std::string& name, const std::vector<double>& data,
                         const std::vector<hsize_t>& shape) {
  write_array(id(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data.data(),
              shape.empty() ? std::vector<hsize_t>{data.size()} : shape);
}

void File::write_dataset(const std::string& name, const std::vector<std::uint32_t>& data) {
  write_array(id(), name, H5T_STD_U32LE, H5T_NATIVE_UINT32, data.data(), {data.size()});
}

bool File::has_attribute(const std::string& name, const std::string& object) const {
  return H5Aexists_by_name(id(), object.c_str(), name.c_str(), local_links(H5P_LINK_ACCESS)) > 0;
}

bool File::has_dataset(const std::string& name) const {
  return H5Lexists(id(), name.c_str(), local_links(H5P_LINK_ACCESS)) > 0;
}

bool File::is_group(const std::string& path) const {
  H5O_info_t info;
  return H5Oget_info_by_name2(id(), path.c_str(), &info, H5O_INFO_BASIC,
                              local_links(H5P_LINK_ACCESS)) >= 0 &&
         info.type == H5O_TYPE_GROUP;
}

hsize_t File::size_bytes() const {
  // The larger of the end of file and the end of allocated space: a file being written may
  // not have reached its end yet. HDF5 refuses to open a file shorter than its superblock says.
  hsize_t size = 0;
  check_status(H5Fget_filesize(id(), &size), path_ + ": cannot read the file size");
  return size;
}

std::vector<std::string> File::list_group(const std::string& group) const {
  Handle g(check(H5Gopen2(id(), group.c_str(), local_links(H5P_GROUP_ACCESS)),
                 fmt::format("{}: missing group '{}'", path_, group)),
           H5Gclose);
  H5G_info_t info;
  check_status(H5Gget_info(g.get(), &info), path_ + ": cannot read group " + group);
  std::vector<std::string> names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t size =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (size < 0) throw std::runtime_error(fmt::format("{}: cannot list group '{}'", path_, group));
    std::string name(static_cast<std::size_t>(size), '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

}  // namespace jam::h5
