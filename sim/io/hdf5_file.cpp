#include "sim/io/hdf5_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sim/io/atomic_file.hpp"
#include "sim/io/output_path.hpp"

namespace jam::h5 {
namespace {

/// "4000" or "2x3": the extent of a simple dataspace, for errors.
std::string extent_words(const std::vector<hsize_t>& dims) {
  std::string s;
  for (std::size_t k = 0; k < dims.size(); ++k) {
    if (k > 0) s += 'x';
    s += std::to_string(dims[k]);
  }
  return s;
}

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

namespace {

/// What a reader asks for: the HDF5 type classes it accepts, in words for its errors.
enum class Kind { kInteger, kNumber, kFloat, kString };

const char* expected_words(Kind kind) {
  switch (kind) {
    case Kind::kInteger:
      return "an integer";
    case Kind::kNumber:
      return "a number";
    case Kind::kFloat:
      return "floating point";
    case Kind::kString:
      return "a string";
  }
  return "";
}

const char* class_words(H5T_class_t cls) {
  switch (cls) {
    case H5T_INTEGER:
      return "an integer";
    case H5T_FLOAT:
      return "a floating-point number";
    case H5T_STRING:
      return "a string";
    case H5T_COMPOUND:
      return "a compound value";
    case H5T_ARRAY:
      return "an array type";
    case H5T_VLEN:
      return "a variable-length sequence";
    case H5T_ENUM:
      return "an enumeration";
    case H5T_REFERENCE:
      return "a reference";
    default:
      return "a value of another HDF5 class";
  }
}

bool accepts(Kind kind, H5T_class_t cls) {
  switch (kind) {
    case Kind::kInteger:
      return cls == H5T_INTEGER;
    case Kind::kNumber:  // an integer converts to a double; no other class converts safely
      return cls == H5T_INTEGER || cls == H5T_FLOAT;
    case Kind::kFloat:
      return cls == H5T_FLOAT;
    case Kind::kString:
      return cls == H5T_STRING;
  }
  return false;
}

/// "attribute 'n'" or "attribute 'n' of 'ensembles/a'".
std::string attribute_label(const std::string& name, const std::string& object) {
  return object == "." || object == "/" ? fmt::format("attribute '{}'", name)
                                        : fmt::format("attribute '{}' of '{}'", name, object);
}

/// Throws `what` unless the type's class is what `kind` accepts, of a size that converts.
void check_type(hid_t type, Kind kind, const std::string& what) {
  const H5T_class_t cls = H5Tget_class(type);
  if (!accepts(kind, cls)) {
    throw std::runtime_error(
        fmt::format("{} is {}, expected {}", what, class_words(cls), expected_words(kind)));
  }
  const std::size_t size = H5Tget_size(type);
  // Numbers of 1-16 bytes convert to int64 or double; other sizes are not numbers jam wrote.
  if (kind != Kind::kString && (size == 0 || size > 16)) {
    throw std::runtime_error(fmt::format("{} is a number of {} bytes", what, size));
  }
  if (kind == Kind::kString && H5Tis_variable_str(type) <= 0 && size > kMaxStringBytes) {
    throw std::runtime_error(fmt::format("{} is a string of {} bytes, longer than the {} allowed",
                                         what, size, kMaxStringBytes));
  }
}

/// Opens attribute `name` of `object` and checks that it holds one value of `kind`.
Handle open_value(hid_t file, const std::string& path, const std::string& name,
                  const std::string& object, Kind kind) {
  const std::string what = path + ": " + attribute_label(name, object);
  Handle attr(H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT,
                              local_links(H5P_LINK_ACCESS)),
              H5Aclose);
  if (attr.get() < 0) {
    throw std::runtime_error(fmt::format("{}: missing attribute '{}'", path, name));
  }
  Handle space(check(H5Aget_space(attr.get()), what + ": unreadable shape"), H5Sclose);
  const std::vector<hsize_t> dims = extent(space.get(), what);
  if (H5Sget_simple_extent_type(space.get()) == H5S_NULL) {
    throw std::runtime_error(what + " holds no value (a null dataspace), expected a scalar");
  }
  if (!dims.empty() && count_values(dims, what) != 1) {
    throw std::runtime_error(
        fmt::format("{} is an array of {}, expected a scalar", what, extent_words(dims)));
  }
  Handle type(check(H5Aget_type(attr.get()), what + ": unreadable type"), H5Tclose);
  check_type(type.get(), kind, what);
  return attr;
}

/// A variable-length string attribute (as h5py writes str), read into memory HDF5 allocates.
std::string read_variable_string(hid_t attr, hid_t file_type, const std::string& what) {
  Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(memory.get(), H5T_VARIABLE);
  H5Tset_cset(memory.get(), H5Tget_cset(file_type));
  char* text = nullptr;
  check_status(H5Aread(attr, memory.get(), &text), what + ": cannot read");
  std::string v = text ? std::string(text, strnlen(text, kMaxStringBytes + 1)) : std::string();
  H5free_memory(text);
  if (v.size() > kMaxStringBytes) {
    throw std::runtime_error(
        fmt::format("{} is a string longer than the {} bytes allowed", what, kMaxStringBytes));
  }
  return v;
}

}  // namespace

double File::read_attribute_double(const std::string& name, const std::string& object) const {
  Handle attr = open_value(id(), path_, name, object, Kind::kNumber);
  double v = 0.0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), path_ + ": cannot read " + name);
  return v;
}

std::int64_t File::read_attribute_int(const std::string& name, const std::string& object) const {
  Handle attr = open_value(id(), path_, name, object, Kind::kInteger);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_sign(type.get()) == H5T_SGN_NONE && H5Tget_size(type.get()) >= 8) {
    // HDF5 would clip an unsigned value beyond 2^63 - 1 to it: a number the file does not hold.
    std::uint64_t u = 0;
    check_status(H5Aread(attr.get(), H5T_NATIVE_UINT64, &u), path_ + ": cannot read " + name);
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      throw std::runtime_error(fmt::format("{}: {} = {} is beyond a signed 64-bit integer", path_,
                                           attribute_label(name, object), u));
    return static_cast<std::int64_t>(u);
  }
  std::int64_t v = 0;
  check_status(H5Aread(attr.get(), H5T_NATIVE_INT64, &v), path_ + ": cannot read " + name);
  return v;
}

std::string File::read_attribute_string(const std::string& name, const std::string& object) const {
  Handle attr = open_value(id(), path_, name, object, Kind::kString);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  const std::string what = path_ + ": " + attribute_label(name, object);
  if (H5Tis_variable_str(type.get()) > 0) return read_variable_string(attr.get(), type.get(), what);
  // One fixed-length string of at most kMaxStringBytes (open_value): the buffer holds it.
  std::string v(H5Tget_size(type.get()), '\0');
  check_status(H5Aread(attr.get(), type.get(), v.data()), path_ + ": cannot read " + name);
  // NULs pad a fixed-length string at its end; one inside the text would cut it silently.
  const std::size_t end = v.find('\0');
  if (end != std::string::npos && v.find_first_not_of('\0', end) != std::string::npos)
    throw std::runtime_error(what + " holds a NUL character inside its text");
  v.resize(end == std::string::npos ? v.size() : end);
  return v;
}

namespace {

/// Opens dataset `name` and checks its shape before anything is read: a simple array of
/// `kind`, no more bytes than the file, written, of the extent the caller expects. Returns the
/// dataset and its number of values.
std::pair<Handle, std::size_t> open_array(const File& f, const std::string& name, Kind kind,
                                          const Extent& expected) {
  const std::string what = fmt::format("{}: dataset '{}'", f.path(), name);
  Handle set(H5Dopen2(f.id(), name.c_str(), local_links(H5P_DATASET_ACCESS)), H5Dclose);
  if (set.get() < 0) {
    H5L_info_t link;
    const bool external =
        H5Lget_info(f.id(), name.c_str(), &link, local_links(H5P_LINK_ACCESS)) >= 0 &&
        link.type == H5L_TYPE_EXTERNAL;
    throw std::runtime_error(external ? what + " is an external link to another file, not followed"
                                      : fmt::format("{}: missing dataset '{}'", f.path(), name));
  }
  if (values_outside_the_file(set.get())) {
    throw std::runtime_error(
        what +
        " keeps its values in another file (external storage or a virtual dataset), "
        "not read");
  }
  Handle space(check(H5Dget_space(set.get()), what + ": unreadable shape"), H5Sclose);
  if (H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE) {
    throw std::runtime_error(what + " is not an array (a scalar or null dataspace)");
  }
  const hsize_t count = count_values(extent(space.get(), what), what);
  Handle type(check(H5Dget_type(set.get()), what + ": unreadable type"), H5Tclose);
  check_type(type.get(), kind, what);
  // Division, not multiplication: a flipped bit can make count * size wrap round.
  const std::size_t size = H5Tget_size(type.get());  // 1 to 16 (check_type)
  if (count > f.size_bytes() / size) {
    throw std::runtime_error(
        fmt::format("{} of {} values of {} bytes is larger than the file ({} bytes)", what, count,
                    size, f.size_bytes()));
  }
  // Declared but never written: HDF5 would fill it with zeros of any size.
  if (count > 0 && H5Dget_storage_size(set.get()) == 0) {
    throw std::runtime_error(fmt::format("{} of {} values was never written", what, count));
  }
  if ((expected.length != Extent::kAny && count != expected.length) || count > expected.max) {
    throw std::runtime_error(fmt::format("{} has {} values, expected {}", what, count,
                                         expected.length != Extent::kAny
                                             ? std::to_string(expected.length)
                                             : fmt::format("at most {}", expected.max)));
  }
  return {std::move(set), static_cast<std::size_t>(count)};
}

template <class T>
std::vector<T> read_array(const File& f, const std::string& name, Kind kind, hid_t memory_type,
                          const Extent& expected) {
  auto [set, count] = open_array(f, name, kind, expected);
  std::vector<T> v(count);
  check_status(H5Dread(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
               f.path() + ": cannot read " + name);
  return v;
}

}  // namespace

std::vector<double> File::read_dataset(const std::string& name, const Extent& expected) const {
  return read_array<double>(*this, name, Kind::kNumber, H5T_NATIVE_DOUBLE, expected);
}

std::vector<double> File::read_float_dataset(const std::string& name,
                                             const Extent& expected) const {
  return read_array<double>(*this, name, Kind::kFloat, H5T_NATIVE_DOUBLE, expected);
}

std::vector<hsize_t> File::dataset_shape(const std::string& name) const {
  const std::string what = fmt::format("{}: dataset '{}'", path_, name);
  Handle set(check(H5Dopen2(id(), name.c_str(), local_links(H5P_DATASET_ACCESS)),
                   fmt::format("{}: missing dataset '{}'", path_, name)),
             H5Dclose);
  Handle space(check(H5Dget_space(set.get()), what + ": unreadable shape"), H5Sclose);
  return extent(space.get(), what);
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

std::vector<std::uint32_t> File::read_dataset_u32(const std::string& name,
                                                  const Extent& expected) const {
  return read_array<std::uint32_t>(*this, name, Kind::kInteger, H5T_NATIVE_UINT32, expected);
}

}  // namespace jam::h5
