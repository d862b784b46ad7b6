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
#include "sim/parallel.hpp"
#include "sim/simd.hpp"

namespace jam {

template <int D>
class NeighborList {
 public:
  explicit NeighborList(double skin = 0.3) : skin_(skin) {}

  double skin() const { return skin_; }
  std::size_t builds() const { return builds_; }
  bool built() const { return builds_ > 0; }
  bool used_cells() const { return used_cells_; }

  /// Threads for builds and rebuild tests (the list itself does not depend on it).
  void set_threads(int threads) { threads_ = threads; }

  const std::vector<std::uint32_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& neighbors() const { return neighbors_; }
  /// The row i of every entry of neighbors() (the pair loop takes pairs two at a time across
  /// rows).
  const std::vector<std::uint32_t>& row_of_pair() const { return row_of_pair_; }
  std::size_t pair_count() const { return neighbors_.size(); }

  /// Bytes held by the list, its cell list and the positions at the build (capacities).
  std::size_t memory_bytes() const {
    std::size_t b = cells_.memory_bytes() + offsets_.capacity() * sizeof(std::uint32_t) +
                    (neighbors_.capacity() + row_of_pair_.capacity()) * sizeof(std::uint32_t);
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
      if (threads_ == 1) {
        neighbors_.resize(build_rows(p, box_length, cut2, 0, n, neighbors_, offsets_.data() + 1));
      } else {
        build_rows_in_parallel(p, box_length, cut2);
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
    row_of_pair_.resize(neighbors_.size());
    for (std::size_t i = 0; i < n; ++i) {
      std::fill(row_of_pair_.begin() + offsets_[i], row_of_pair_.begin() + offsets_[i + 1],
                static_cast<std::uint32_t>(i));
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
    const std::size_t n = p.size();
    // Quick sufficient test first: delta_1 + delta_2 <= 2 max_i delta_i (exactly so in floating
    // point too), so when twice the largest displacement fits, the exact test would say "no
    // rebuild" as well. The largest alone takes one packed max per two particles, where the
    // exact two largest need a compare-and-shift per particle.
    const auto quick = for_blocks<LargestOne>(
        n, [&](std::size_t a, std::size_t b) { return largest_displacement(p, a, b); });
    if (!quick.not_finite && box_length * (2.0 * std::sqrt(quick.largest)) <= margin) return false;
    const auto all = for_blocks<LargestTwo>(
        n, [&](std::size_t a, std::size_t b) { return largest_displacements(p, a, b); });
    return all.not_finite || box_length * (std::sqrt(all.first) + std::sqrt(all.second)) > margin;
  }

  /// Forget the build (after particles were reordered or replaced).
  void invalidate() { valid_ = false; }

 private:
  static double distance2(const ParticleData<D>& p, std::size_t i, std::size_t j, double L) {
    std::array<double, D> dr;
    return pair_separation(p, i, j, L, dr);
  }

  /// Squared scaled displacement of particle i since the build (minimum image).
  double displacement2(const ParticleData<D>& p, std::size_t i) const {
    double d2 = 0.0;
    for (int d = 0; d < D; ++d) {
      const double ds = minimum_image(p.s[d][i] - s_at_build_[d][i]);
      d2 += ds * ds;
    }
    return d2;
  }

  /// The two largest squared scaled displacements since the build, and whether any is NaN.
  struct LargestTwo {
    double first = 0.0, second = 0.0;
    bool not_finite = false;
    void add(double d2) {
      not_finite |= !(d2 == d2);  // NaN: force a build, which reports it
      if (d2 > second) {
        second = std::min(d2, first);
        first = std::max(d2, first);
      }
    }
    void merge(const LargestTwo& o) {
      add(o.first);
      add(o.second);
      not_finite |= o.not_finite;
    }
  };

  /// The largest squared scaled displacement since the build, and whether any is NaN.
  struct LargestOne {
    double largest = 0.0;
    bool not_finite = false;
    void merge(const LargestOne& o) {
      largest = std::max(largest, o.largest);
      not_finite |= o.not_finite;
    }
  };

  LargestOne largest_displacement(const ParticleData<D>& p, std::size_t first,
                                  std::size_t last) const {
    LargestOne out;
    std::size_t i = first;
#if defined(__SSE2__)
    __m128d largest = _mm_setzero_pd(), nan = _mm_setzero_pd();
    for (; i + 1 < last; i += 2) {
      __m128d d2 = _mm_setzero_pd();
      for (int d = 0; d < D; ++d) {
        const __m128d ds = _mm_sub_pd(_mm_loadu_pd(&p.s[d][i]), _mm_loadu_pd(&s_at_build_[d][i]));
        const __m128d image = minimum_image(ds);
        d2 = _mm_add_pd(d2, _mm_mul_pd(image, image));
      }
      nan = _mm_or_pd(nan, _mm_cmpunord_pd(d2, d2));
      largest = _mm_max_pd(d2, largest);
    }
    alignas(16) double lanes[2], nans[2];
    _mm_store_pd(lanes, largest);
    _mm_store_pd(nans, nan);
    out.largest = std::max(lanes[0], lanes[1]);
    out.not_finite = _mm_movemask_pd(_mm_load_pd(nans)) != 0;
#endif
    for (; i < last; ++i) {
      const double d2 = displacement2(p, i);
      out.not_finite |= !(d2 == d2);
      out.largest = std::max(out.largest, d2);
    }
    return out;
  }

  /// f(first, last) over contiguous blocks of [0, n), one per thread, merged in block order.
  template <class Result, class F>
  Result for_blocks(std::size_t n, F&& f) const {
    if (threads_ == 1) return f(std::size_t{0}, n);
    Result all;
#if defined(_OPENMP)
    std::array<Result, 64> block{};
    const auto threads = static_cast<std::size_t>(std::min(threads_, 64));
#pragma omp parallel num_threads(static_cast <int>(threads))
    {
      const auto t = static_cast<std::size_t>(thread_number());
      block[t] = f(n * t / threads, n * (t + 1) / threads);
    }
    for (std::size_t t = 0; t < threads; ++t) all.merge(block[t]);
#endif
    return all;
  }

  LargestTwo largest_displacements(const ParticleData<D>& p, std::size_t first,
                                   std::size_t last) const {
    LargestTwo out;
    for (std::size_t i = first; i < last; ++i) out.add(displacement2(p, i));
    return out;
  }

  /// Rows first .. last-1 of the list into out (grown as needed), starting at out[0]; row i
  /// ends at row_end[i - first]. Returns the number of entries written.
  ///
  /// Candidates are written unconditionally and kept by advancing the count: whether a
  /// candidate is a neighbor is a coin flip, which as a branch would be mispredicted often.
  std::size_t build_rows(const ParticleData<D>& p, double box_length,
                         const std::array<double, 3>& cut2, std::size_t first, std::size_t last,
                         std::vector<std::uint32_t>& out, std::uint32_t* row_end) const {
    std::size_t count = 0;
    std::size_t last_home = static_cast<std::size_t>(-1);
    std::array<std::size_t, kStencilCells> stencil{};
    std::size_t candidates = 0;
    for (std::size_t i = first; i < last; ++i) {
      const std::size_t home = cells_.cell_of(i);
      if (home != last_home) {  // consecutive particles mostly share a cell (sorted start)
        stencil_of(cells_.coordinates(home), stencil);
        candidates = 0;
        for (std::size_t c : stencil) candidates += cells_.size(c);
        last_home = home;
      }
      if (out.size() < count + candidates) out.resize(2 * (count + candidates));
      std::uint32_t* row = out.data();
      const std::size_t row_start = count;
      const int ti = p.type[i];
      for (std::size_t c : stencil) {
        for (const std::uint32_t* it = cells_.begin(c); it != cells_.end(c); ++it) {
          const std::uint32_t j = *it;
          row[count] = j;
          count += static_cast<std::size_t>(j > i) &
                   static_cast<std::size_t>(distance2(p, i, j, box_length) < cut2[ti + p.type[j]]);
        }
      }
      // Ascending j within each row: the list, and so the force summation order, depends
      // only on the configuration, not on the cell traversal.
      insertion_sort(row + row_start, row + count);
      row_end[i - first] = static_cast<std::uint32_t>(count);
    }
    return count;
  }

  /// The same list as build_rows over all particles: thread t builds a contiguous block of
  /// rows into its own buffer, and the blocks are then joined in order.
  void build_rows_in_parallel(const ParticleData<D>& p, double box_length,
                              const std::array<double, 3>& cut2) {
#if defined(_OPENMP)
    const std::size_t n = p.size();
    const auto threads = static_cast<std::size_t>(threads_);
    block_rows_.resize(threads);
    std::vector<std::size_t> first(threads + 1), count(threads), base(threads + 1, 0);
    for (std::size_t t = 0; t <= threads; ++t) first[t] = n * t / threads;
#pragma omp parallel num_threads(threads_)
    {
      const auto t = static_cast<std::size_t>(thread_number());
      count[t] = build_rows(p, box_length, cut2, first[t], first[t + 1], block_rows_[t],
                            offsets_.data() + 1 + first[t]);
#pragma omp barrier
#pragma omp single
      {
        for (std::size_t u = 0; u < threads; ++u) base[u + 1] = base[u] + count[u];
        neighbors_.resize(base[threads]);
      }
      std::copy(block_rows_[t].begin(),
                block_rows_[t].begin() + static_cast<std::ptrdiff_t>(count[t]),
                neighbors_.begin() + static_cast<std::ptrdiff_t>(base[t]));
      for (std::size_t i = first[t]; i < first[t + 1]; ++i)
        offsets_[i + 1] += static_cast<std::uint32_t>(base[t]);
    }
#else
    (void)p, (void)box_length, (void)cut2;
#endif
  }

  static constexpr std::size_t kStencilCells = D == 2 ? 9 : 27;

  /// The 3^D cells around (and including) the cell at integer coordinates home, periodic.
  void stencil_of(const std::array<int, D>& home,
                  std::array<std::size_t, kStencilCells>& out) const {
    const int m = cells_.cells_per_side();
    std::array<std::array<int, 3>, D> wrapped;  // home[d] - 1, home[d], home[d] + 1 wrapped
    for (int d = 0; d < D; ++d) {
      wrapped[d] = {home[d] == 0 ? m - 1 : home[d] - 1, home[d],
                    home[d] == m - 1 ? 0 : home[d] + 1};
    }
    std::size_t k = 0;
    if constexpr (D == 2) {
      for (int b : wrapped[1])
        for (int a : wrapped[0]) out[k++] = cells_.index_of_wrapped({a, b});
    } else {
      for (int c : wrapped[2])
        for (int b : wrapped[1])
          for (int a : wrapped[0]) out[k++] = cells_.index_of_wrapped({a, b, c});
    }
  }

  /// Rows hold a few to a few tens of entries: insertion sort beats std::sort's set-up.
  static void insertion_sort(std::uint32_t* first, std::uint32_t* last) {
    for (std::uint32_t* it = first + (first != last); it < last; ++it) {
      const std::uint32_t v = *it;
      std::uint32_t* hole = it;
      while (hole != first && *(hole - 1) > v) {
        *hole = *(hole - 1);
        --hole;
      }
      *hole = v;
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
  std::vector<std::uint32_t> row_of_pair_;
  int threads_ = 1;
  std::vector<std::vector<std::uint32_t>> block_rows_;  // per-thread rows of a parallel build
};

}  // namespace jam
