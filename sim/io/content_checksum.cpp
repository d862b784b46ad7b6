#include "sim/io/content_checksum.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <set>
#include <stdexcept>

#include "sim/io/fnv1a.hpp"

namespace jam {
namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error(what);
}

/// What a walk over a file has seen: the hash, the objects visited (by address, so that a link
/// back to a group already on the way is a loop, not an endless recursion) and how many bytes
/// of values it may still read. Every value is stored once in an uncompressed file, so the
/// values of a sound file take at most its size: a flipped dimension asking for more is
/// corrupt before anything is allocated.
struct Walk {
  Fnv1a hash;
  const std::vector<std::string>& skip;
  hsize_t budget;  // bytes of values (in the file's types) left
  std::set<haddr_t> visited;
  int depth = 0;
};

// jam's files nest groups three deep; deeper nesting is damage (and would grow the stack).
constexpr int kMaxDepth = 32;

struct Link {
  std::string name;
  H5L_type_t type;
};

herr_t collect_name(hid_t, const char* name, const H5A_info_t*, void* names) {
  static_cast<std::vector<std::string>*>(names)->push_back(name);
  return 0;
}

herr_t collect_link(hid_t, const char* name, const H5L_info_t* info, void* links) {
  static_cast<std::vector<Link>*>(links)->push_back({name, info->type});
  return 0;
}

/// Takes `count` values of `file_type` out of the walk's budget; throws when they do not fit.
void spend(Walk& walk, hid_t file_type, hsize_t count, const std::string& what) {
  const std::size_t size = H5Tget_size(file_type);
  check(size > 0, "cannot read the type of " + what);
  if (count > walk.budget / size) {
    throw std::runtime_error(
        fmt::format("{}: {} values of {} bytes do not fit in the file's {} bytes", what, count,
                    size, walk.budget));
  }
  walk.budget -= count * size;
}

/// Reads an attribute or dataset of class cls in a canonical memory type: integers as int64,
/// floats as double, strings as their bytes.
void add_values(Walk& walk, H5T_class_t cls, hid_t file_type, hsize_t count,
                const std::function<herr_t(hid_t, void*)>& read, const std::string& what) {
  spend(walk, file_type, count, what);
  Fnv1a& hash = walk.hash;
  const auto n = static_cast<std::size_t>(count);
  hash.add(&cls, sizeof cls);
  if (cls == H5T_INTEGER) {
    std::vector<std::int64_t> v(n);
    check(read(H5T_NATIVE_INT64, v.data()) >= 0, "cannot read " + what);
    hash.add(v.data(), v.size() * sizeof(std::int64_t));
  } else if (cls == H5T_FLOAT) {
    std::vector<double> v(n);
    check(read(H5T_NATIVE_DOUBLE, v.data()) >= 0, "cannot read " + what);
    hash.add(v.data(), v.size() * sizeof(double));
  } else if (cls == H5T_STRING && H5Tis_variable_str(file_type) <= 0) {
    std::string v(n * H5Tget_size(file_type), '\0');
    check(read(file_type, v.data()) >= 0, "cannot read " + what);
    hash.add_sized(v.substr(0, v.find_last_not_of('\0') + 1));
  } else {
    throw std::runtime_error(what + ": a kind of value the checksum does not cover");
  }
}

void add_attributes(Walk& walk, hid_t object, const std::string& where) {
  std::vector<std::string> names;
  hsize_t at = 0;
  check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, &at, collect_name, &names) >= 0,
        "cannot list the attributes of " + where);
  for (const auto& name : names) {
    if (where == "/" && std::find(walk.skip.begin(), walk.skip.end(), name) != walk.skip.end()) {
      continue;
    }
    h5::Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
    check(attr.get() >= 0, "cannot open attribute " + name);
    h5::Handle type(H5Aget_type(attr.get()), H5Tclose);
    h5::Handle space(H5Aget_space(attr.get()), H5Sclose);
    check(type.get() >= 0 && space.get() >= 0, "cannot read attribute " + name);
    const hsize_t count = h5::values_in(space.get(), "attribute " + where + name);
    walk.hash.add_sized("attribute " + where + name);
    add_values(
        walk, H5Tget_class(type.get()), type.get(), count,
        [&](hid_t mem, void* buf) { return H5Aread(attr.get(), mem, buf); }, name);
  }
}

void add_group(Walk& walk, hid_t group, const std::string& where);

void add_dataset(Walk& walk, hid_t set, const std::string& path) {
  h5::Handle type(H5Dget_type(set), H5Tclose);
  h5::Handle space(H5Dget_space(set), H5Sclose);
  check(type.get() >= 0 && space.get() >= 0, "cannot read the shape of " + path);
  const std::vector<hsize_t> dims = h5::extent(space.get(), path);
  walk.hash.add_sized("dataset " + path);
  walk.hash.add(dims.data(), dims.size() * sizeof(hsize_t));
  const hsize_t count = h5::values_in(space.get(), path);
  // Declared but never written (a chunked dataset with no chunks): HDF5 would make up its
  // values; whatever the size, the file does not hold them.
  // Values kept in another file (external storage, a virtual dataset): jam writes none, and
  // reading them would open a file nothing has checked.
  check(!h5::values_outside_the_file(set),
        path + ": keeps its values in another file, not written by jam");
  check(count == 0 || H5Dget_storage_size(set) > 0,
        fmt::format("{}: {} values declared but never written", path, count));
  add_values(
      walk, H5Tget_class(type.get()), type.get(), count,
      [&](hid_t mem, void* buf) { return H5Dread(set, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); },
      path);
  add_attributes(walk, set, path + "@");
}

/// Opens the object a hard link names, once: an object reached twice is a loop of links.
h5::Handle open_once(Walk& walk, hid_t group, const Link& link, const std::string& path) {
  // jam writes hard links only; a soft or external link could point anywhere, even outside
  // the file.
  check(link.type == H5L_TYPE_HARD, path + ": a soft or external link, not written by jam");
  h5::Handle object(H5Oopen(group, link.name.c_str(), H5P_DEFAULT), H5Oclose);
  check(object.get() >= 0, "cannot open " + path);
  H5O_info_t info;
  check(H5Oget_info2(object.get(), &info, H5O_INFO_BASIC) >= 0, "cannot read " + path);
  check(walk.visited.insert(info.addr).second,
        path + ": an object reached twice (a loop of links: the file is damaged)");
  return object;
}

void add_group(Walk& walk, hid_t group, const std::string& where) {
  check(++walk.depth <= kMaxDepth, where + ": groups nested deeper than the file can be sound");
  add_attributes(walk, group, where);
  std::vector<Link> links;
  hsize_t at = 0;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &at, collect_link, &links) >= 0,
        "cannot list " + where);
  for (const auto& link : links) {
    const std::string path = where + link.name;
    h5::Handle object = open_once(walk, group, link, path);
    if (H5Iget_type(object.get()) == H5I_GROUP) {
      walk.hash.add_sized("group " + path);
      add_group(walk, object.get(), path + "/");
    } else if (H5Iget_type(object.get()) == H5I_DATASET) {
      add_dataset(walk, object.get(), path);
    } else {
      throw std::runtime_error(path + ": neither a group nor a dataset");
    }
  }
  --walk.depth;
}

}  // namespace

std::uint64_t content_checksum(const h5::File& f, const std::vector<std::string>& skip) {
  Walk walk{Fnv1a{}, skip, f.size_bytes(), {}, 0};
  H5O_info_t root;
  check(H5Oget_info2(f.id(), &root, H5O_INFO_BASIC) >= 0, f.path() + ": cannot read its root");
  walk.visited.insert(root.addr);
  try {
    add_group(walk, f.id(), "/");
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: corrupt: {}", f.path(), e.what()));
  }
  return walk.hash.value();
}

std::uint64_t bytes_checksum(const std::string& bytes) {
  Fnv1a hash;
  hash.add(bytes);
  return hash.value();
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
