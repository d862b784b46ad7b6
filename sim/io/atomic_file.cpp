#include "sim/io/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "sim/io/output_path.hpp"

namespace jam {

std::string write_failure(const std::string& path, int error) {
  if (error == 0 || error == EIO) {
    const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
    struct statvfs fs {};
    if (::statvfs(parent.c_str(), &fs) == 0 && fs.f_bavail == 0) error = ENOSPC;
  }
  return error != 0 ? std::strerror(error) : "I/O error";
}

int rename_no_replace(const std::string& from, const std::string& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return 0;
  if (errno != EINVAL && errno != ENOSYS) return errno;
  // A file system without RENAME_NOREPLACE: link() fails with EEXIST instead of replacing.
  if (::link(from.c_str(), to.c_str()) != 0) return errno;
  return ::unlink(from.c_str()) == 0 ? 0 : errno;
}

std::string move_aside(const std::string& path, const std::string& suffix) {
  // A bounded search: ten thousand set-aside copies of one run mean something else is wrong.
  for (int k = 0; k < 10000; ++k) {
    const std::string aside = k == 0 ? path + suffix : fmt::format("{}{}.{}", path, suffix, k);
    const int error = rename_no_replace(path, aside);
    if (error == 0) return aside;
    if (error != EEXIST && error != ENOTEMPTY) {
      throw WriteError(fmt::format("cannot move '{}' aside: {}", path, std::strerror(error)));
    }
  }
  throw WriteError(fmt::format("cannot move '{}' aside: 10000 names '{}{}.*' already taken", path,
                               path, suffix));
}

void copy_file_atomically(const std::string& from, const std::string& given) {
  const std::string to = output_file_target(given);
  const std::string temporary = AtomicFile::temporary_name(to);
  std::error_code ec;
  std::filesystem::copy_file(from, temporary, std::filesystem::copy_options::overwrite_existing,
                             ec);
  if (ec) {
    // The cause is judged while the partial copy still takes its space (a full disk can answer
    // EIO; write_failure calls it full only when no block is left).
    const std::string why = write_failure(to, ec.value());
    std::filesystem::remove(temporary);
    throw WriteError(fmt::format("cannot copy '{}' to '{}': {}", from, to, why));
  }
  AtomicFile::publish(to);
}

std::string AtomicFile::temporary_name(const std::string& path) {
  // The process and the thread: two runs of one campaign process may write the same file at
  // once (the relaxed start two rates of a sample share); each writes its own temporary and
  // the last rename wins, with identical contents.
  return fmt::format("{}.{}-{}.partial", path, ::getpid(), ::gettid());
}

AtomicFile::AtomicFile(std::string path)
    : path_(output_file_target(path)), temporary_(temporary_name(path_)) {
  stream_ = std::fopen(temporary_.c_str(), "w");
  if (!stream_) {
    throw WriteError(fmt::format("cannot write '{}': {}", path_, std::strerror(errno)));
  }
}

AtomicFile::~AtomicFile() {
  if (stream_) std::fclose(stream_);
  if (!committed_) std::remove(temporary_.c_str());
}

void AtomicFile::commit() {
  const bool write_failed = std::ferror(stream_) != 0;
  const bool close_failed = std::fclose(stream_) != 0;
  stream_ = nullptr;
  if (write_failed || close_failed) {
    throw WriteError(fmt::format("cannot write '{}': {}", path_, write_failure(path_, errno)));
  }
  publish(path_);
  committed_ = true;
}

void AtomicFile::publish(const std::string& path) {
  if (std::rename(temporary_name(path).c_str(), path.c_str()) != 0) {
    throw WriteError(fmt::format("cannot rename to '{}': {}", path, std::strerror(errno)));
  }
}

}  // namespace jam
