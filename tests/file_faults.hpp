#pragma once
// Damage planted in files, for the tests of what jam trusts on disk.
#include <sys/mount.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"

namespace jam::test {

/// Flips one bit of the first occurrence of the 8 bytes of `value` in the file; false when the
/// value is not there. A low mantissa bit: the value stays finite and plausible.
inline bool flip_bit_of(const std::filesystem::path& file, double value) {
  std::string bytes = slurp(file);
  char pattern[sizeof value];
  std::memcpy(pattern, &value, sizeof value);
  const auto at = bytes.find(std::string(pattern, sizeof value));
  if (at == std::string::npos) return false;
  bytes[at + 1] ^= 0x10;
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  return true;
}

/// Flips one bit of the first occurrence of `text` in the file; false when it is not there.
inline bool flip_bit_of_text(const std::filesystem::path& file, const std::string& text) {
  std::string bytes = slurp(file);
  const auto at = bytes.find(text);
  if (at == std::string::npos) return false;
  bytes[at] ^= 0x01;
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  return true;
}

/// A small tmpfs mounted at `dir` for the life of the object, for real full-disk faults.
/// Mounting needs root: `mounted` says whether it happened (tests skip with a message if not).
struct SmallTmpfs {
  std::filesystem::path dir;
  bool mounted = false;
  SmallTmpfs(std::filesystem::path where, const std::string& size) : dir(std::move(where)) {
    std::filesystem::create_directories(dir);
    mounted = ::geteuid() == 0 &&
              ::mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
  }
  SmallTmpfs(const SmallTmpfs&) = delete;
  SmallTmpfs& operator=(const SmallTmpfs&) = delete;
  ~SmallTmpfs() {
    if (mounted) ::umount2(dir.c_str(), MNT_DETACH);
  }
  /// Fills the file system with dir/filler, then gives `free_bytes` back.
  void fill(std::uintmax_t free_bytes = 0) const {
    const std::filesystem::path filler = dir / "filler";
    {
      std::ofstream out(filler, std::ios::binary | std::ios::app);
      const std::string block(4096, 'x');
      while (out.write(block.data(), block.size())) {
      }
    }
    const std::uintmax_t size = std::filesystem::file_size(filler);
    std::filesystem::resize_file(filler, size > free_bytes ? size - free_bytes : 0);
  }
  void empty() const { std::filesystem::remove(dir / "filler"); }
};

}  // namespace jam::test
