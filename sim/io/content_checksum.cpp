#include "sim/io/content_checksum.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>

namespace jam {
namespace {

constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

struct Hash {
  std::uint64_t h = kFnvOffset;
  void bytes(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) {
      h ^= b[k];
      h *= kFnvPrime;
    }
  }
  void text(const std::string& s) {
    const std::uint64_t size = s.size();
    bytes(&size, sizeof size);
    bytes(s.data(), s.size());
  }
};

void check(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error(what);
}

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

/// Reads an attribute or dataset of class cls in a canonical memory type: integers as int64,
/// floats as double, strings as their bytes.
void add_values(Hash& hash, H5T_class_t cls, hid_t file_type, std::size_t count,
                const std::function<herr_t(hid_t, void*)>& read, const std::string& what) {
  hash.bytes(&cls, sizeof cls);
  if (cls == H5T_INTEGER) {
    std::vector<std::int64_t> v(count);
    check(read(H5T_NATIVE_INT64, v.data()) >= 0, "cannot read " + what);
    hash.bytes(v.data(), v.size() * sizeof(std::int64_t));
  } else if (cls == H5T_FLOAT) {
    std::vector<double> v(count);
    check(read(H5T_NATIVE_DOUBLE, v.data()) >= 0, "cannot read " + what);
    hash.bytes(v.data(), v.size() * sizeof(double));
  } else if (cls == H5T_STRING && H5Tis_variable_str(file_type) <= 0) {
    std::string v(count * H5Tget_size(file_type), '\0');
    check(read(file_type, v.data()) >= 0, "cannot read " + what);
    hash.text(v.substr(0, v.find_last_not_of('\0') + 1));
  } else {
    throw std::runtime_error(what + ": a kind of value the checksum does not cover");
  }
}

void add_attributes(Hash& hash, hid_t object, const std::string& where,
                    const std::vector<std::string>& skip) {
  std::vector<std::string> names;
  hsize_t at = 0;
  check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, &at, collect_name, &names) >= 0,
        "cannot list the attributes of " + where);
  for (const auto& name : names) {
    if (where == "/" && std::find(skip.begin(), skip.end(), name) != skip.end()) continue;
    h5::Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
    check(attr.get() >= 0, "cannot open attribute " + name);
    h5::Handle type(H5Aget_type(attr.get()), H5Tclose);
    h5::Handle space(H5Aget_space(attr.get()), H5Sclose);
    const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
    hash.text("attribute " + where + name);
    add_values(
        hash, H5Tget_class(type.get()), type.get(), count,
        [&](hid_t mem, void* buf) { return H5Aread(attr.get(), mem, buf); }, name);
  }
}

void add_group(Hash& hash, hid_t group, const std::string& where,
               const std::vector<std::string>& skip) {
  add_attributes(hash, group, where, skip);
  std::vector<std::string> names;
  hsize_t at = 0;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &at, collect_link, &names) >= 0,
        "cannot list " + where);
  for (const auto& name : names) {
    h5::Handle object(H5Oopen(group, name.c_str(), H5P_DEFAULT), H5Oclose);
    check(object.get() >= 0, "cannot open " + where + name);
    const std::string path = where + name;
    if (H5Iget_type(object.get()) == H5I_GROUP) {
      hash.text("group " + path);
      add_group(hash, object.get(), path + "/", skip);
      continue;
    }
    h5::Handle type(H5Dget_type(object.get()), H5Tclose);
    h5::Handle space(H5Dget_space(object.get()), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    check(rank >= 0, "cannot read the shape of " + path);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
    hash.text("dataset " + path);
    hash.bytes(dims.data(), dims.size() * sizeof(hsize_t));
    const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
    add_values(
        hash, H5Tget_class(type.get()), type.get(), count,
        [&](hid_t mem, void* buf) {
          return H5Dread(object.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
        },
        path);
    add_attributes(hash, object.get(), path + "@", skip);
  }
}

}  // namespace

std::uint64_t content_checksum(const h5::File& f, const std::vector<std::string>& skip) {
  Hash hash;
  add_group(hash, f.id(), "/", skip);
  return hash.h;
}

std::string checksum_text(std::uint64_t h) {
  return fmt::format("{:016x}", h);
}

void seal(h5::File& f) {
  f.write_attribute("checksum", checksum_text(content_checksum(f, {"checksum"})));
}

std::string seal_problem(const h5::File& f) {
  if (!f.has_attribute("checksum")) return "no checksum (written before checksums were kept)";
  const std::string stored = f.read_attribute_string("checksum");
  const std::string actual = checksum_text(content_checksum(f, {"checksum"}));
  if (stored != actual) {
    return fmt::format("checksum {} does not match the stored {}", actual, stored);
  }
  return "";
}

}  // namespace jam
