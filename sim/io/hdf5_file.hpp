#pragma once
// A thin RAII layer over the HDF5 C API: just what run files need (scalar attributes,
// string attributes, 1-D and N-D double datasets), with errors turned into exceptions.
// Object modification times are not recorded, so identical runs give identical files.
#include <hdf5.h>

#include <cstdint>
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

/// The Debian HDF5 library is built without thread safety: every File holds this lock for
/// its lifetime, so runs on several threads of a campaign never call HDF5 concurrently.
std::mutex& library_mutex();

class File {
 public:
  /// Truncates. A user block of `user_block` bytes (0 or a power of two >= 512) is left at the
  /// start of the file for the caller (sealed_file.hpp).
  static File create(const std::string& path, hsize_t user_block = 0);
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
  bool has_dataset(const std::string& name) const;
  double read_attribute_double(const std::string& name, const std::string& object = ".") const;
  std::int64_t read_attribute_int(const std::string& name, const std::string& object = ".") const;
  std::string read_attribute_string(const std::string& name, const std::string& object = ".") const;
  std::vector<double> read_dataset(const std::string& name) const;
  /// Names of the links (groups, datasets) directly inside a group, in name order.
  std::vector<std::string> list_group(const std::string& group) const;
  std::vector<std::uint32_t> read_dataset_u32(const std::string& name) const;

 private:
  File(std::unique_lock<std::mutex> lock, Handle h, std::string path)
      : lock_(std::move(lock)), file_(std::move(h)), path_(std::move(path)) {}
  std::unique_lock<std::mutex> lock_;  // declared first: released after the file is closed
  Handle file_;
  std::string path_;
};

}  // namespace jam::h5
