#pragma once
// A thin RAII layer over the HDF5 C API (writing and opening in hdf5_file.cpp, the checked
// reading in hdf5_read.cpp): just what run files need (scalar attributes,
// string attributes, 1-D and N-D double datasets), with errors turned into exceptions.
// Object modification times are not recorded, so identical runs give identical files.
//
// Reading checks shapes before values, because a file may come from anywhere (a damaged copy,
// a hand edit, a forged checksum) and HDF5 writes as many values as the file says into the
// caller's buffer:
// - a scalar attribute holds one value: a scalar dataspace or an array of exactly one element
//   (the value is the same either way, and the run file's checksum treats them alike), of the
//   class asked for (an integer; a number, integer or floating-point; a string, fixed-length
//   of at most kMaxStringBytes or variable-length);
// - a dataset is a simple array of the class asked for, whose values take no more bytes than
//   the whole file (jam writes uncompressed data), that was written (not only declared), and
//   whose number of values is what the caller expects (Extent).
// Anything else throws std::runtime_error "<file>: attribute 'complete' is an array of 4000,
// expected a scalar" (naming the file, the object and what is wrong). Only a regular file is
// opened: a FIFO would block the open for ever; for the same reason an external link (to
// another file) is never followed.
#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace jam::h5 {

class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  ~Handle() { reset(); }
  void reset();
  /// Forgets the id without closing it.
  void release() { id_ = -1; }
  hid_t get() const { return id_; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

/// The longest string attribute read (the longest jam writes, the units, is a few hundred).
constexpr std::size_t kMaxStringBytes = 1 << 16;

/// What a reader expects of a dataset's number of values (every rank flattened).
struct Extent {
  static constexpr std::size_t kAny = std::numeric_limits<std::size_t>::max();
  std::size_t length = kAny;  // exactly this many (kAny: any number)
  std::size_t max = kAny;     // at most this many
};
inline Extent exactly(std::size_t n) {
  return {n, n};
}
inline Extent at_most(std::size_t n) {
  return {Extent::kAny, n};
}

/// Access properties (H5P_LINK_ACCESS, H5P_DATASET_ACCESS or H5P_GROUP_ACCESS) under which
/// paths are resolved within the file: an external link is refused, never followed.
hid_t local_links(hid_t property_class);
/// Whether a dataset keeps its values outside its file: external storage (raw data in other
/// files) or a virtual dataset (mapped from datasets of other files). Reading those would open
/// files no check has seen (a FIFO there blocks the read for ever); jam writes neither.
bool values_outside_the_file(hid_t dataset);

/// The extent of a dataspace ({} for a scalar or null one); throws naming `what` if unreadable.
std::vector<hsize_t> extent(hid_t space, const std::string& what);
/// The product of an extent; throws naming `what` when it overflows.
hsize_t count_values(const std::vector<hsize_t>& dims, const std::string& what);
/// The number of values a dataspace holds: 1 when scalar, 0 when null.
hsize_t values_in(hid_t space, const std::string& what);

/// The Debian HDF5 library is built without thread safety: every File holds this lock for
/// its lifetime, so runs on several threads of a campaign never call HDF5 concurrently.
std::mutex& library_mutex();

class File {
 public:
  /// Truncates. A user block of `user_block` bytes (0 or a power of two >= 512) is left at the
  /// start of the file for the caller (sealed_file.hpp).
  static File create(const std::string& path, hsize_t user_block = 0);
  /// Opens a regular file (anything else is refused before it is opened, naming what it is).
  static File open_read(const std::string& path);
  hid_t id() const { return file_.get(); }
  const std::string& path() const { return path_; }
  /// Flushes and closes; throws when HDF5 could not write everything (a full disk, an I/O
  /// error), so that a file written under a temporary name is never published half-written.
  void close();

  // Attributes of the object at `object` (a group or dataset path; "." is the root).
  void write_attribute(const std::string& name, double value, const std::string& object = ".");
  void write_attribute(const std::string& name, std::int64_t value,
                       const std::string& object = ".");
  void write_attribute(const std::string& name, const std::string& value,
                       const std::string& object = ".");
  /// Creates a group and any missing parents.
  void create_group(const std::string& path);
  void write_dataset(const std::string& name, const std::vector<double>& data,
                     const std::vector<hsize_t>& shape = {});

  void write_dataset(const std::string& name, const std::vector<std::uint32_t>& data);

  bool has_attribute(const std::string& name, const std::string& object = ".") const;
  /// Whether a link of that name exists (a group or a dataset: jam's readers ask of either).
  bool has_dataset(const std::string& name) const;
  /// Whether `path` names a group (not a dataset, not a link that leaves the file).
  bool is_group(const std::string& path) const;
  double read_attribute_double(const std::string& name, const std::string& object = ".") const;
  std::int64_t read_attribute_int(const std::string& name, const std::string& object = ".") const;
  std::string read_attribute_string(const std::string& name, const std::string& object = ".") const;
  /// Floating-point values, every rank flattened.
  std::vector<double> read_dataset(const std::string& name, const Extent& expected = {}) const;
  /// As read_dataset, but only a floating-point dataset: an integer one is refused, not converted.
  std::vector<double> read_float_dataset(const std::string& name,
                                         const Extent& expected = {}) const;
  /// The extent of a dataset (its rank is the vector's length; {} for a scalar), read before
  /// any value so that a reader can refuse a table where it expects a list.
  std::vector<hsize_t> dataset_shape(const std::string& name) const;
  /// Names of the links (groups, datasets) directly inside a group, in name order.
  std::vector<std::string> list_group(const std::string& group) const;
  std::vector<std::uint32_t> read_dataset_u32(const std::string& name,
                                              const Extent& expected = {}) const;
  /// The file's size in bytes: no dataset of it can hold more.
  hsize_t size_bytes() const;

 private:
  File(std::unique_lock<std::mutex> lock, Handle h, std::string path)
      : lock_(std::move(lock)), file_(std::move(h)), path_(std::move(path)) {}
  std::unique_lock<std::mutex> lock_;  // declared first: released after the file is closed
  Handle file_;
  std::string path_;
};

}  // namespace jam::h5
