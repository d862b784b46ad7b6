#include "sim/io/hdf5_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "sim/io/atomic_file.hpp"

namespace jam::h5 {
namespace {

hid_t check(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error(what);
  return id;
}

void check_status(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error(what);
}

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

}  // namespace

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

template <class T>
std::vector<T> read_array(hid_t file, const std::string& path, const std::string& name,
                          hid_t memory_type) {
  Handle set(check(H5Dopen2(file, name.c_str(), H5P_DEFAULT),
                   fmt::format("{}: missing dataset '{}'", path, name)),
             H5Dclose);
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  std::vector<T> v(static_cast<std::size_t>(count < 0 ? 0 : count));
  check_status(H5Dread(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
               path + ": cannot read " + name);
  return v;
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
  return H5Aexists_by_name(id(), object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

bool File::has_dataset(const std::string& name) const {
  return H5Lexists(id(), name.c_str(), H5P_DEFAULT) > 0;
}

namespace {
Handle open_attribute(hid_t file, const std::string& path, const std::string& name,
                      const std::string& object) {
  return Handle(check(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                      fmt::format("{}: missing attribute '{}'", path, name)),
                H5Aclose);
}
}  // namespace

double File::read_attribute_double(const std::string& name, const std::string& object) const {
  Handle attr = open_attribute(id(), path_, name, object);
  double v = 0.0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), path_ + ": cannot read " + name);
  return v;
}

std::int64_t File::read_attribute_int(const std::string& name, const std::string& object) const {
  Handle attr = open_attribute(id(), path_, name, object);
  std::int64_t v = 0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_INT64, &v), path_ + ": cannot read " + name);
  return v;
}

std::string File::read_attribute_string(const std::string& name, const std::string& object) const {
  Handle attr = open_attribute(id(), path_, name, object);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  const std::size_t size = H5Tget_size(type.get());
  std::string v(size, '\0');
  check_status(H5Aread(attr.get(), type.get(), v.data()), path_ + ": cannot read " + name);
  v.resize(v.find('\0') == std::string::npos ? v.size() : v.find('\0'));
  return v;
}

std::vector<double> File::read_dataset(const std::string& name) const {
  return read_array<double>(id(), path_, name, H5T_NATIVE_DOUBLE);
}

std::vector<std::string> File::list_group(const std::string& group) const {
  Handle g(check(H5Gopen2(id(), group.c_str(), H5P_DEFAULT),
                 fmt::format("{}: missing group '{}'", path_, group)),
           H5Gclose);
  H5G_info_t info;
  check_status(H5Gget_info(g.get(), &info), path_ + ": cannot read group " + group);
  std::vector<std::string> names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const ssize_t size =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    std::string name(static_cast<std::size_t>(size), '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

std::vector<std::uint32_t> File::read_dataset_u32(const std::string& name) const {
  return read_array<std::uint32_t>(id(), path_, name, H5T_NATIVE_UINT32);
}

}  // namespace jam::h5
