#include "campaign/import_store.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "sim/io/atomic_file.hpp"

namespace jam {
namespace {

/// A new file at `path`, opened for writing: O_EXCL refuses anything already there, a link
/// included (with O_CREAT | O_EXCL a link is never followed), and O_NOFOLLOW says so twice.
int create_new(const std::string& path, const std::string& target) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0)
    throw WriteError(fmt::format("cannot write '{}': {}", target, write_failure(target, errno)));
  return fd;
}

/// Writes all of data to fd; false (errno set) on a failed or short write.
bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t wrote = ::write(fd, data, size);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) return false;
    data += wrote;
    size -= static_cast<std::size_t>(wrote);
  }
  return true;
}

}  // namespace

Temporary::~Temporary() {
  if (!path_.empty()) ::unlink(path_.c_str());
}

std::string copy_to_temporary(const std::string& from, const std::string& to) {
  const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) throw WriteError(fmt::format("cannot read '{}': {}", from, std::strerror(errno)));
  const std::string temporary = AtomicFile::temporary_name(to);
  int out = -1;
  try {
    out = create_new(temporary, to);
  } catch (...) {
    ::close(in);
    throw;
  }
  Temporary guard(temporary);
  std::vector<char> buffer(1 << 16);
  int error = 0;
  for (;;) {
    const ssize_t got = ::read(in, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 || (got > 0 && !write_all(out, buffer.data(), static_cast<std::size_t>(got)))) {
      error = errno != 0 ? errno : EIO;
      break;
    }
    if (got == 0) break;
  }
  ::close(in);
  if (::close(out) != 0 && error == 0) error = errno;
  if (error != 0)
    throw WriteError(
        fmt::format("cannot copy '{}' to '{}': {}", from, to, write_failure(to, error)));
  guard.release();
  return temporary;
}

void write_replacing(const std::string& path, const std::string& text) {
  const std::string temporary = AtomicFile::temporary_name(path);
  const int fd = create_new(temporary, path);
  Temporary guard(temporary);
  const bool wrote = write_all(fd, text.data(), text.size());
  int error = wrote ? 0 : (errno != 0 ? errno : EIO);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (!wrote || error != 0)
    throw WriteError(fmt::format("cannot write '{}': {}", path, write_failure(path, error)));
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
    throw WriteError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  guard.release();
}

}  // namespace jam
