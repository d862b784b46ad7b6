#pragma once
// A file that appears under its final name only when complete: written to "<path>.partial"
// and renamed by commit(). Destroyed without commit(), it removes the partial file, so an
// error never leaves output that could be mistaken for a result.
#include <cstdio>
#include <string>

namespace jam {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  std::FILE* stream() { return stream_; }
  const std::string& temporary_path() const { return temporary_; }
  void commit();

  /// Temporary name used for path (also for files written by other libraries, e.g. HDF5).
  static std::string temporary_name(const std::string& path) { return path + ".partial"; }
  /// Renames temporary_name(path) to path; throws naming the path on failure.
  static void publish(const std::string& path);

 private:
  std::string path_, temporary_;
  std::FILE* stream_ = nullptr;
  bool committed_ = false;
};

}  // namespace jam
