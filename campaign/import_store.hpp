#pragma once
// The files `jam campaign import` writes into an external campaign (external.toml and
// runs/<name>.h5) are written so that nothing else is ever written through or over: each goes
// to a temporary of its own (AtomicFile::temporary_name, <path>.<pid>-<tid>.partial) that is
// created with O_EXCL | O_NOFOLLOW, so a file or a symbolic link already at that name is never
// opened, and is then renamed. A rename replaces a link itself, never the file it points to.
#include <string>

namespace jam {

/// A temporary file removed when this goes out of scope, unless released (renamed into place).
class Temporary {
 public:
  explicit Temporary(std::string path) : path_(std::move(path)) {}
  Temporary(const Temporary&) = delete;
  Temporary& operator=(const Temporary&) = delete;
  ~Temporary();
  const std::string& path() const { return path_; }
  void release() { path_.clear(); }

 private:
  std::string path_;
};

/// Copies `from` into a new temporary beside `to` (created, never opened if there); throws
/// WriteError naming `to` and the cause. The copy's bytes are checksummed by the caller.
std::string copy_to_temporary(const std::string& from, const std::string& to);

/// Writes `text` to `path` through a new temporary renamed over whatever is at `path` (a file
/// of this import's own: external.toml). Throws WriteError naming the path and the cause.
void write_replacing(const std::string& path, const std::string& text);

}  // namespace jam
