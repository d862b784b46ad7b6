#include "sim/io/atomic_file.hpp"

#include <fmt/format.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace jam {

std::string write_failure(const std::string& path, int error) {
  if (error == 0 || error == EIO) {
    const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
    struct statvfs fs {};
    if (::statvfs(parent.c_str(), &fs) == 0 && fs.f_bavail == 0) error = ENOSPC;
  }
  return error != 0 ? std::strerror(error) : "I/O error";
}

std::string AtomicFile::temporary_name(const std::string& path) {
  // The process and the thread: two runs of one campaign process may write the same file at
  // once (the relaxed start two rates of a sample share); each writes its own temporary and
  // the last rename wins, with identical contents.
  return fmt::format("{}.{}-{}.partial", path, ::getpid(), ::gettid());
}

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), temporary_(temporary_name(path_)) {
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
