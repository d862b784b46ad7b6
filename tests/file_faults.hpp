#pragma once
// Damage planted in files, for the tests of what jam trusts on disk.
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

}  // namespace jam::test
