#pragma once
// Pairs (i, j) as an ordered set, to compare a neighbor list with the O(N^2) oracle.
#include <cstdint>
#include <set>
#include <utility>

#include "sim/neighbor/neighbor_list.hpp"

namespace jam::testing {

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

/// Every pair of a half neighbor list.
template <int D>
PairSet listed_pairs(const NeighborList<D>& list) {
  PairSet s;
  const auto& off = list.offsets();
  for (std::uint32_t i = 0; i + 1 < off.size(); ++i)
    for (std::uint32_t k = off[i]; k < off[i + 1]; ++k) s.emplace(i, list.neighbors()[k]);
  return s;
}

}  // namespace jam::testing
