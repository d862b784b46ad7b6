#pragma once
// Verlet (half) neighbor list with a skin, built from a cell list, stored as CSR: the
// neighbors j > i of particle i are neighbors()[offsets()[i] .. offsets()[i+1]).
//
// A pair is listed when, at the build, r < d_ij + skin. Between builds the box shrinks by
// lambda = L / L_build and particles move non-affinely by delta_i (physical, at the current
// box). A pair that was not listed has r >= lambda (d_ij + skin) - (delta_i + delta_j), so no
// contact can be missed while
//     delta_1 + delta_2 <= lambda skin - (1 - lambda) d_max,                          (*)
// with delta_1, delta_2 the two largest displacements. needs_rebuild() tests (*).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"
#include "sim/neighbor/cell_list.hpp"

namespace jam {

template <int D>
class NeighborList {
 public:
  explicit NeighborList(double skin = 0.3) : skin_(skin) {}

  double skin() const { return skin_; }
  std::size_t builds() const { return builds_; }
  bool built() const { return builds_ > 0; }
  bool used_cells() const { return used_cells_; }

  const std::vector<std::uint32_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& neighbors() const { return neighbors_; }
  std::size_t pair_count() const { return neighbors_.size(); }

  /// Bytes held by the list, its cell list and the positions at the build (capacities).
  std::size_t memory_bytes() const {
    std::size_t b = cells_.memory_bytes() + offsets_.capacity() * sizeof(std::uint32_t) +
                    neighbors_.capacity() * sizeof(std::uint32_t);
    for (const auto& s : s_at_build_) b += s.capacity() * sizeof(double);
    return b;
  }

  /// Number of cells per side for a box of length L: cells at least d_max + skin wide.
  int cells_per_side(const Species<D>& species, double box_length) const {
    return static_cast<int>(std::floor(box_length / (species.max_contact_distance + skin_)));
  }

  void build(const ParticleData<D>& p, const Species<D>& species, double box_length) {
    const std::size_t n = p.size();
    offsets_.assign(n + 1, 0);
    neighbors_.clear();
    std::array<double, 3> cut2{};
    for (int k = 0; k < 3; ++k) {
      const double c = species.contact_distance[k] + skin_;
      cut2[k] = c * c;
    }
    for (int d = 0; d < D; ++d) {
      for (std::size_t i = 0; i < n; ++i) {
        if (!(p.s[d][i] >= 0.0 && p.s[d][i] < 1.0)) {
          throw std::runtime_error(
              "particle positions became non-finite or left the box: the dynamics is unstable "
              "(reduce --dt)");
        }
      }
    }
    const int m = cells_per_side(species, box_length);
    used_cells_ = m >= 3;  // a 3^D stencil with fewer cells would visit a cell twice
    if (used_cells_) {
      cells_.build(p, m);
      for (std::size_t i = 0; i < n; ++i) {
        const auto home = cells_.coordinates(cells_.cell_of(i));
        for_each_stencil_cell(home, [&](std::size_t c) {
          for (const std::uint32_t* it = cells_.begin(c); it != cells_.end(c); ++it) {
            const std::uint32_t j = *it;
            if (j > i && distance2(p, i, j, box_length) < cut2[p.type[i] + p.type[j]]) {
              neighbors_.push_back(j);
            }
          }
        });
        // Ascending j within each row: the list, and so the force summation order, depends
        // only on the configuration, not on the cell traversal.
        std::sort(neighbors_.begin() + offsets_[i], neighbors_.end());
        offsets_[i + 1] = static_cast<std::uint32_t>(neighbors_.size());
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
          if (distance2(p, i, j, box_length) < cut2[p.type[i] + p.type[j]]) {
            neighbors_.push_back(static_cast<std::uint32_t>(j));
          }
        }
        offsets_[i + 1] = static_cast<std::uint32_t>(neighbors_.size());
      }
    }
    for (int d = 0; d < D; ++d) s_at_build_[d] = p.s[d];
    length_at_build_ = box_length;
    max_contact_distance_ = species.max_contact_distance;
    ++builds_;
    valid_ = true;
  }

  /// True when criterion (*) could be violated at box length L, or the list was never built.
  bool needs_rebuild(const ParticleData<D>& p, double box_length) const {
    if (!valid_ || p.size() + 1 != offsets_.size()) return true;
    const double lambda = box_length / length_at_build_;
    const double margin = lambda * skin_ - (1.0 - lambda) * max_contact_distance_;
    if (margin <= 0.0) return true;
    double first = 0.0, second = 0.0;  // two largest squared scaled displacements
    bool not_finite = false;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
      double d2 = 0.0;
      for (int d = 0; d < D; ++d) {
        const double ds = minimum_image(p.s[d][i] - s_at_build_[d][i]);
        d2 += ds * ds;
      }
      not_finite |= !(d2 == d2);  // NaN: force a build, which reports it
      if (d2 > second) {
        second = std::min(d2, first);
        first = std::max(d2, first);
      }
    }
    return not_finite || box_length * (std::sqrt(first) + std::sqrt(second)) > margin;
  }

  /// Forget the build (after particles were reordered or replaced).
  void invalidate() { valid_ = false; }

 private:
  static double distance2(const ParticleData<D>& p, std::size_t i, std::size_t j, double L) {
    std::array<double, D> dr;
    return pair_separation(p, i, j, L, dr);
  }

  template <class F>
  void for_each_stencil_cell(const std::array<int, D>& home, F&& visit) const {
    std::array<int, D> k{};
    if constexpr (D == 2) {
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          k = {home[0] + a, home[1] + b};
          visit(cells_.index(k));
        }
    } else {
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b)
          for (int c = -1; c <= 1; ++c) {
            k = {home[0] + a, home[1] + b, home[2] + c};
            visit(cells_.index(k));
          }
    }
  }

  double skin_;
  std::size_t builds_ = 0;
  bool used_cells_ = false;
  bool valid_ = false;
  double length_at_build_ = 0.0;
  double max_contact_distance_ = 0.0;
  CellList<D> cells_;
  std::array<std::vector<double>, D> s_at_build_;
  std::vector<std::uint32_t> offsets_;
  std::vector<std::uint32_t> neighbors_;
};

}  // namespace jam
