#pragma once
// O(N^2) reference search: every pair i < j closer than d_ij + extra. The oracle the fast
// neighbor list is tested against, and the fallback for boxes too small for a 3^D cell stencil.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"

namespace jam {

template <int D>
std::vector<std::pair<std::uint32_t, std::uint32_t>> brute_force_pairs(const ParticleData<D>& p,
                                                                       const Species<D>& species,
                                                                       double box_length,
                                                                       double extra) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      std::array<double, D> dr;
      const double r2 = pair_separation(p, i, j, box_length, dr);
      const double cut = species.contact_distance[p.type[i] + p.type[j]] + extra;
      if (r2 < cut * cut) {
        pairs.emplace_back(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      }
    }
  }
  return pairs;
}

}  // namespace jam
