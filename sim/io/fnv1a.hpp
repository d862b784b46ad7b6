#pragma once
// FNV-1a, 64 bit: the one hash of jam's files. Run files (data_checksum, checksum), sealed
// checkpoints and chained starts ("jam-seal fnv1a64"), chained starts' keys and an import's
// source_checksum all store it, so its bytes must never change: tests/test_fnv1a.cpp pins the
// published test vectors and one value of each stored use. A guard against damage (bit rot, a
// torn copy, a hand edit), not against someone who forges files on purpose.
#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace jam {

class Fnv1a {
 public:
  static constexpr std::uint64_t kOffset = 0xcbf29ce484222325ULL;
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;

  constexpr Fnv1a() = default;

  /// Adds n bytes, in order.
  void add(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) {
      h_ ^= b[k];
      h_ *= kPrime;
    }
  }

  /// Adds the characters of s (not its length: see add_sized).
  void add(std::string_view s) { add(s.data(), s.size()); }

  /// Adds the bytes of one value of a trivially copyable type, as it lies in memory.
  template <class T>
  void add_value(const T& v) {
    add(&v, sizeof v);
  }

  /// Adds s's length (64 bit, in memory order) and then its characters, so that ("ab", "c")
  /// and ("a", "bc") differ.
  void add_sized(std::string_view s) {
    add_value(std::uint64_t{s.size()});
    add(s);
  }

  constexpr std::uint64_t value() const { return h_; }

  /// The hash as stored: 16 lowercase hex digits.
  std::string hex() const { return fmt::format("{:016x}", h_); }

 private:
  std::uint64_t h_ = kOffset;
};

}  // namespace jam
