#pragma once
// Counts read as doubles (a LAMMPS log's steps and atoms, a TOML file's sizes and samples) are
// taken as integers only when they are whole numbers in range: a fraction would be truncated
// without a word, and a double outside int64's range converts to an undefined value.

#include <cmath>
#include <cstdint>
#include <optional>

namespace jam {

/// 2^53: a double holds every whole number up to it exactly, so a count read as a double
/// converts to an integer without loss.
inline constexpr std::int64_t kMaxExactWhole = std::int64_t{1} << 53;

/// v as an integer when it is a whole number in [lo, hi] (bounds within +-kMaxExactWhole);
/// nullopt for anything else, NaN and infinities included.
inline std::optional<std::int64_t> whole_number(double v, std::int64_t lo, std::int64_t hi) {
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi) && v == std::floor(v)))
    return std::nullopt;
  return static_cast<std::int64_t>(v);
}

}  // namespace jam
