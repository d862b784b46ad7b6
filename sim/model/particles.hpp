#pragma once
// Particle data, structure of arrays. Positions are stored in scaled (box) coordinates
// s in [0,1)^D; the physical position relative to the box centre is r = L(t) (s - 1/2).
// In these coordinates the host flow v_host = -rate r (paper, "Model") is the box shrinking
// itself, so the affine part of the motion is exact and never accumulates round-off.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "sim/simd.hpp"

namespace jam {

template <int D>
struct ParticleData {
  std::array<std::vector<double>, D> s;  // scaled positions, each in [0, 1)
  std::vector<std::uint8_t> type;        // kSmall or kBig
  std::vector<std::uint32_t> id;         // 1-based LAMMPS atom id, kept through reordering

  std::size_t size() const { return type.size(); }

  void resize(std::size_t n) {
    for (auto& c : s) c.resize(n);
    type.resize(n);
    id.resize(n);
  }

  std::size_t count(int species) const {
    std::size_t c = 0;
    for (auto t : type) c += (t == species);
    return c;
  }
};

/// Wraps a scaled coordinate into [0, 1). The rare out-of-range case is a well-predicted branch.
inline double wrap_unit(double x) {
  if (x < 0.0 || x >= 1.0) {
    x -= std::floor(x);
    if (x >= 1.0) x = 0.0;  // -tiny - floor(-tiny) rounds to exactly 1
  }
  return x;
}

/// Minimum-image separation of two scaled coordinates in [0,1): result in [-1/2, 1/2].
/// ds - nearest_integer(ds), with the rounding done by adding and subtracting 1.5 * 2^52: for
/// |ds| < 2^51 the sum has no fraction bits left, so round-to-nearest-even does the rounding
/// (ties at |ds| = 1/2 go to 0, as ds > 1/2 ? 1 : 0 would). No comparison, so no branch the
/// compiler could introduce, and the same bits as ds - 1, ds or ds + 1 would give.
/// (Needs the default rounding mode and no -ffast-math, which could cancel the two constants.)
inline constexpr double kMinimumImageShift = 6755399441055744.0;  // 1.5 * 2^52

inline double minimum_image(double ds) {
  const double nearest = (ds + kMinimumImageShift) - kMinimumImageShift;
  return ds - nearest;
}

#if defined(__SSE2__)
/// minimum_image of two separations at once, the same operations (so the same bits) per lane.
inline __m128d minimum_image(__m128d ds) {
  const __m128d shift = _mm_set1_pd(kMinimumImageShift);
  return _mm_sub_pd(ds, _mm_sub_pd(_mm_add_pd(ds, shift), shift));
}
#endif

#if defined(JAM_AVX2_FORMS)
/// minimum_image of four separations at once (AVX2), the same operations per lane.
__attribute__((target("avx2"))) inline __m256d minimum_image(__m256d ds) {
  const __m256d shift = _mm256_set1_pd(kMinimumImageShift);
  return _mm256_sub_pd(ds, _mm256_sub_pd(_mm256_add_pd(ds, shift), shift));
}
#endif

/// Physical minimum-image separation r_i - r_j at box length L into dr; returns |dr|^2.
template <int D>
double pair_separation(const ParticleData<D>& p, std::size_t i, std::size_t j, double box_length,
                       std::type_identity_t<std::array<double, D>>& dr) {
  double r2 = 0.0;
  for (int d = 0; d < D; ++d) {
    dr[d] = box_length * minimum_image(p.s[d][i] - p.s[d][j]);
    r2 += dr[d] * dr[d];
  }
  return r2;
}

}  // namespace jam
