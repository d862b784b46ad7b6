#include "sim/io/sealed_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "sim/io/atomic_file.hpp"
#include "sim/io/fnv1a.hpp"

namespace jam {
namespace {

struct Closer {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, Closer>;

/// FNV-1a (64 bit) of the bytes from kSealBytes to the end; the count through `bytes`.
std::uint64_t hash_after_seal(std::FILE* f, std::uint64_t& bytes) {
  Fnv1a h;
  bytes = 0;
  std::vector<unsigned char> buffer(1 << 16);
  if (std::fseek(f, static_cast<long>(kSealBytes), SEEK_SET) != 0) return h.value();
  for (std::size_t got; (got = std::fread(buffer.data(), 1, buffer.size(), f)) > 0;) {
    h.add(buffer.data(), got);
    bytes += got;
  }
  return h.value();
}

std::string seal_text(std::uint64_t h, std::uint64_t bytes) {
  return fmt::format("jam-seal fnv1a64 {:016x} {}\n", h, bytes);
}

}  // namespace

void seal_file(const std::string& path) {
  FilePtr f(std::fopen(path.c_str(), "r+b"));
  if (!f) throw WriteError(fmt::format("cannot seal '{}': {}", path, std::strerror(errno)));
  std::uint64_t bytes = 0;
  const std::uint64_t h = hash_after_seal(f.get(), bytes);
  std::string block = seal_text(h, bytes);
  block.resize(kSealBytes, '\0');
  if (std::fseek(f.get(), 0, SEEK_SET) != 0 ||
      std::fwrite(block.data(), 1, block.size(), f.get()) != block.size() ||
      std::fflush(f.get()) != 0) {
    throw WriteError(fmt::format("cannot seal '{}': {}", path, write_failure(path, errno)));
  }
}

namespace {

const char* kind(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

std::string sealed_file_problem(const std::string& path) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer; what was opened
  // is then checked by its descriptor, so nothing can be swapped in between.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return fmt::format("cannot read: {}", std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const int error = errno;
    ::close(fd);
    return S_ISREG(st.st_mode)
               ? fmt::format("cannot read: {}", std::strerror(error))
               : fmt::format("is {}; only a regular file can be read", kind(st.st_mode));
  }
  FilePtr f(::fdopen(fd, "rb"));
  if (!f) {
    ::close(fd);
    return fmt::format("cannot read: {}", std::strerror(errno));
  }
  char block[kSealBytes + 1] = {};
  if (std::fread(block, 1, kSealBytes, f.get()) != kSealBytes) return "shorter than its seal";
  if (std::strncmp(block, "jam-seal ", 9) != 0) {
    return "no seal (not written by this version of jam)";
  }
  std::uint64_t bytes = 0;
  const std::uint64_t h = hash_after_seal(f.get(), bytes);
  const std::string expected = seal_text(h, bytes);
  if (std::strncmp(block, expected.c_str(), expected.size()) != 0) {
    return "its bytes do not match its seal (damaged or changed since it was written)";
  }
  return "";
}

}  // namespace jam
