#pragma once
// A file that appears under its final name only when complete (a symbolic link to a regular
// file is written through, and a FIFO, device or directory there refused: output_path.hpp):
// written to
// "<path>.<pid>-<tid>.partial" and renamed by commit(). The process and thread ids keep two
// processes, or two runs of one campaign process, that write the same name from writing into,
// or renaming, each other's file (temporary_name, atomic_file.cpp). Destroyed
// without commit(), it removes the partial file, so an error never leaves output that could be
// mistaken for a result.
#include <cstdio>
#include <stdexcept>
#include <string>

namespace jam {

/// Output could not be written (unwritable directory, full disk, I/O error): a fault of the
/// machine, not of the run, so a campaign leaves the run to be redone rather than failed.
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Why writing `path` failed, in words: strerror(error), except that an unspecific error (EIO,
/// or none recorded, as HDF5 leaves it) on a file system with no free blocks left is said to be
/// what it is, "No space left on device".
std::string write_failure(const std::string& path, int error);

/// Renames `from` to `to` only when nothing is at `to` (not even a dangling link): 0, or the
/// errno (EEXIST when something is there). renameat2 with RENAME_NOREPLACE, or link and unlink
/// where the file system lacks it.
int rename_no_replace(const std::string& from, const std::string& to);

/// Moves `path` aside to the first free name of `path + suffix`, `path + suffix + ".1"`, ".2", ...
/// and returns it. Never replaces an existing file (renameat2 with RENAME_NOREPLACE, or link and
/// unlink where the file system lacks it), so a file set aside earlier is never lost, even when
/// two processes set aside at once.
std::string move_aside(const std::string& path, const std::string& suffix);

/// Copies `from` to `to` through a temporary renamed when complete: a full disk leaves no
/// truncated copy under the final name. Throws WriteError naming `to` and the cause.
void copy_file_atomically(const std::string& from, const std::string& to);

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  std::FILE* stream() { return stream_; }
  const std::string& temporary_path() const { return temporary_; }
  void commit();

  /// Temporary name used for path (also for files written by other libraries, e.g. HDF5), unique
  /// to this process and thread; publish(path) must be called from the same thread.
  static std::string temporary_name(const std::string& path);
  /// Renames temporary_name(path) to path; throws naming the path on failure.
  static void publish(const std::string& path);

 private:
  std::string path_, temporary_;
  std::FILE* stream_ = nullptr;
  bool committed_ = false;
};

}  // namespace jam
