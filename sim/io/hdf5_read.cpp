// Reading an HDF5 file with every shape and class checked before a value is read (the
// contract is in hdf5_file.hpp): attributes, datasets and their extents. Writing, opening and
// listing are in hdf5_file.cpp.
#include <fmt/format.h>

#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sim/io/hdf5_errors.hpp"
#include "sim/io/hdf5_file.hpp"

namespace jam::h5 {

using detail::check;
using detail::check_status;
using detail::extent_words;

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

std::vector<std::uint32_t> File::read_dataset_u32(const std::string& name,
                                                  const Extent& expected) const {
  return read_array<std::uint32_t>(*this, name, Kind::kInteger, H5T_NATIVE_UINT32, expected);
}

}  // namespace jam::h5
