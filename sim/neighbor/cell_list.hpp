#pragma once
// Cell list in scaled coordinates: m cells per side, particles bucketed by a counting sort
// (cell_start / members, a CSR layout), so building is O(N) and allocation-free once sized.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/model/particles.hpp"

namespace jam {

template <int D>
class CellList {
 public:
  /// Buckets the particles into cells_per_side^D cells.
  void build(const ParticleData<D>& p, int cells_per_side) {
    m_ = cells_per_side;
    std::size_t ncell = 1;
    for (int d = 0; d < D; ++d) ncell *= static_cast<std::size_t>(m_);
    const std::size_t n = p.size();
    cell_of_.resize(n);
    cell_start_.assign(ncell + 1, 0);
    members_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t c = 0;
      for (int d = D - 1; d >= 0; --d) {
        int k = static_cast<int>(p.s[d][i] * m_);
        k = k < m_ ? k : m_ - 1;
        c = c * static_cast<std::size_t>(m_) + static_cast<std::size_t>(k);
      }
      cell_of_[i] = static_cast<std::uint32_t>(c);
      ++cell_start_[c + 1];
    }
    for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
    fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      members_[fill_[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }

  int cells_per_side() const { return m_; }
  std::size_t cell_of(std::size_t i) const { return cell_of_[i]; }

  /// Integer coordinates of cell c.
  std::array<int, D> coordinates(std::size_t c) const {
    std::array<int, D> k{};
    for (int d = 0; d < D; ++d) {
      k[d] = static_cast<int>(c % static_cast<std::size_t>(m_));
      c /= static_cast<std::size_t>(m_);
    }
    return k;
  }

  /// Linear index of integer cell coordinates already in [0, m).
  std::size_t index_of_wrapped(const std::array<int, D>& k) const {
    std::size_t c = 0;
    for (int d = D - 1; d >= 0; --d)
      c = c * static_cast<std::size_t>(m_) + static_cast<std::size_t>(k[d]);
    return c;
  }

  std::size_t size(std::size_t c) const { return cell_start_[c + 1] - cell_start_[c]; }

  const std::uint32_t* begin(std::size_t c) const { return members_.data() + cell_start_[c]; }
  const std::uint32_t* end(std::size_t c) const { return members_.data() + cell_start_[c + 1]; }

  /// Particle indices ordered cell by cell: a locality-improving permutation.
  const std::vector<std::uint32_t>& members() const { return members_; }

  /// Bytes held by the cell list (capacities of its arrays).
  std::size_t memory_bytes() const {
    return cell_of_.capacity() * sizeof(std::uint32_t) +
           members_.capacity() * sizeof(std::uint32_t) +
           (cell_start_.capacity() + fill_.capacity()) * sizeof(std::size_t);
  }

 private:
  int m_ = 0;
  std::vector<std::uint32_t> cell_of_;
  std::vector<std::size_t> cell_start_;
  std::vector<std::size_t> fill_;
  std::vector<std::uint32_t> members_;
};

}  // namespace jam
