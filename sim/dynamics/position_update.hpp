#pragma once
// The overdamped position updates of one scaled coordinate over particles [first, last):
//  - advance_coordinate: s_i <- wrap(s_i + c[type_i] f_i), forward Euler's step after the
//    forces (c = dt mobility / L by species);
//  - heun_predict / heun_correct: Heun's two stages (overdamped_heun.hpp);
//  - hermite_coordinate: out_i <- wrap(s0_i + y_i(theta)), the cubic Hermite continuous
//    extension of the Chebyshev integrator's step (overdamped_chebyshev.hpp, dense output).
// The compiler does not vectorize the plain loops (the per-species factor and the wrap's rare
// branch), so where the processor has AVX2 four particles share each instruction; the
// operations per particle are the same IEEE ones in the same order (no FMA), and a group of
// four with a coordinate leaving [0, 1) is wrapped by wrap_unit itself, so both forms give the
// same bits (tests/test_position_update.cpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"
#include "sim/simd.hpp"

namespace jam {

/// The reference form, one particle at a time.
inline void advance_coordinate_scalar(double* s, const double* f, const std::uint8_t* type,
                                      const std::array<double, 2>& c, std::size_t first,
                                      std::size_t last) {
  for (std::size_t i = first; i < last; ++i) s[i] = wrap_unit(s[i] + c[type[i]] * f[i]);
}

/// Heun's predictor: s0_i <- s_i, slope_i <- c[type_i] f_i, s_i <- wrap(s_i + dt slope_i).
inline void heun_predict_scalar(double* s, double* s0, double* slope, const double* f,
                                const std::uint8_t* type, const std::array<double, 2>& c, double dt,
                                std::size_t first, std::size_t last) {
  for (std::size_t i = first; i < last; ++i) {
    s0[i] = s[i];
    slope[i] = c[type[i]] * f[i];
    s[i] = wrap_unit(s[i] + dt * slope[i]);
  }
}

/// Heun's corrector: s_i <- wrap(s0_i + (dt/2) (slope_i + c[type_i] f_i)).
inline void heun_correct_scalar(double* s, const double* s0, const double* slope, const double* f,
                                const std::uint8_t* type, const std::array<double, 2>& c,
                                double half_dt, std::size_t first, std::size_t last) {
  for (std::size_t i = first; i < last; ++i)
    s[i] = wrap_unit(s0[i] + half_dt * (slope[i] + c[type[i]] * f[i]));
}

/// The step's continuous extension at theta = (t - t_n) / h: y = a F_n + b (3 Delta - h (2 F_n +
/// F_{n+1})) + c (-2 Delta + h (F_n + F_{n+1})) with a = theta h, b = theta^2, c = theta^3, from
/// the slopes at both ends (fn, fn1) and the step's displacement (delta).
struct HermiteWeights {
  double h, a, b, c;
};

inline void hermite_coordinate_scalar(double* out, const double* s0, const double* fn,
                                      const double* fn1, const double* delta,
                                      const HermiteWeights& w, std::size_t first,
                                      std::size_t last) {
  for (std::size_t i = first; i < last; ++i) {
    const double y = w.a * fn[i] + w.b * (3.0 * delta[i] - w.h * (2.0 * fn[i] + fn1[i])) +
                     w.c * (-2.0 * delta[i] + w.h * (fn[i] + fn1[i]));
    out[i] = wrap_unit(s0[i] + y);
  }
}

#if defined(JAM_AVX2_FORMS)
/// c[type_i] for particles i ... i + 3.
__attribute__((target("avx2"), always_inline)) inline __m256d species_factor(
    const std::uint8_t* type, const std::array<double, 2>& c) {
  std::int32_t types;
  std::memcpy(&types, type, sizeof types);
  const __m256i t = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(types));
  const __m256i big = _mm256_cmpeq_epi64(t, _mm256_set1_epi64x(kBig));
  return _mm256_blendv_pd(_mm256_set1_pd(c[0]), _mm256_set1_pd(c[1]), _mm256_castsi256_pd(big));
}

/// s[0..3] <- wrap_unit(x) lane by lane (one packed store when all are in [0, 1), the rare
/// boundary crossing through wrap_unit itself).
__attribute__((target("avx2"), always_inline)) inline void store_wrapped(double* s, __m256d x) {
  const __m256d outside = _mm256_or_pd(_mm256_cmp_pd(x, _mm256_setzero_pd(), _CMP_LT_OQ),
                                       _mm256_cmp_pd(x, _mm256_set1_pd(1.0), _CMP_GE_OQ));
  if (_mm256_movemask_pd(outside) == 0) {
    _mm256_storeu_pd(s, x);
    return;
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, x);
  for (int l = 0; l < 4; ++l) s[l] = wrap_unit(lanes[l]);
}

/// Four particles per AVX2 instruction (only where cpu_has_avx2()); the scalar forms' bits.
__attribute__((target("avx2"))) inline void advance_coordinate_avx2(double* s, const double* f,
                                                                    const std::uint8_t* type,
                                                                    const std::array<double, 2>& c,
                                                                    std::size_t first,
                                                                    std::size_t last) {
  std::size_t i = first;
  for (; i + 3 < last; i += 4) {
    const __m256d ci = species_factor(type + i, c);
    store_wrapped(s + i,
                  _mm256_add_pd(_mm256_loadu_pd(s + i), _mm256_mul_pd(ci, _mm256_loadu_pd(f + i))));
  }
  advance_coordinate_scalar(s, f, type, c, i, last);
}

__attribute__((target("avx2"))) inline void heun_predict_avx2(
    double* s, double* s0, double* slope, const double* f, const std::uint8_t* type,
    const std::array<double, 2>& c, double dt, std::size_t first, std::size_t last) {
  const __m256d step = _mm256_set1_pd(dt);
  std::size_t i = first;
  for (; i + 3 < last; i += 4) {
    const __m256d x = _mm256_loadu_pd(s + i);
    const __m256d k = _mm256_mul_pd(species_factor(type + i, c), _mm256_loadu_pd(f + i));
    _mm256_storeu_pd(s0 + i, x);
    _mm256_storeu_pd(slope + i, k);
    store_wrapped(s + i, _mm256_add_pd(x, _mm256_mul_pd(step, k)));
  }
  heun_predict_scalar(s, s0, slope, f, type, c, dt, i, last);
}

__attribute__((target("avx2"))) inline void heun_correct_avx2(
    double* s, const double* s0, const double* slope, const double* f, const std::uint8_t* type,
    const std::array<double, 2>& c, double half_dt, std::size_t first, std::size_t last) {
  const __m256d half_step = _mm256_set1_pd(half_dt);
  std::size_t i = first;
  for (; i + 3 < last; i += 4) {
    const __m256d k1 = _mm256_mul_pd(species_factor(type + i, c), _mm256_loadu_pd(f + i));
    const __m256d sum = _mm256_add_pd(_mm256_loadu_pd(slope + i), k1);
    store_wrapped(s + i, _mm256_add_pd(_mm256_loadu_pd(s0 + i), _mm256_mul_pd(half_step, sum)));
  }
  heun_correct_scalar(s, s0, slope, f, type, c, half_dt, i, last);
}

__attribute__((target("avx2"))) inline void hermite_coordinate_avx2(
    double* out, const double* s0, const double* fn, const double* fn1, const double* delta,
    const HermiteWeights& w, std::size_t first, std::size_t last) {
  const __m256d h = _mm256_set1_pd(w.h), a = _mm256_set1_pd(w.a), b = _mm256_set1_pd(w.b),
                c = _mm256_set1_pd(w.c), two = _mm256_set1_pd(2.0), three = _mm256_set1_pd(3.0),
                minus_two = _mm256_set1_pd(-2.0);
  std::size_t i = first;
  for (; i + 3 < last; i += 4) {
    const __m256d f0 = _mm256_loadu_pd(fn + i), f1 = _mm256_loadu_pd(fn1 + i),
                  d = _mm256_loadu_pd(delta + i);
    const __m256d first_term = _mm256_mul_pd(a, f0);
    const __m256d second_term = _mm256_mul_pd(
        b, _mm256_sub_pd(_mm256_mul_pd(three, d),
                         _mm256_mul_pd(h, _mm256_add_pd(_mm256_mul_pd(two, f0), f1))));
    const __m256d third_term = _mm256_mul_pd(
        c, _mm256_add_pd(_mm256_mul_pd(minus_two, d), _mm256_mul_pd(h, _mm256_add_pd(f0, f1))));
    const __m256d y = _mm256_add_pd(_mm256_add_pd(first_term, second_term), third_term);
    store_wrapped(out + i, _mm256_add_pd(_mm256_loadu_pd(s0 + i), y));
  }
  hermite_coordinate_scalar(out, s0, fn, fn1, delta, w, i, last);
}
#endif

/// The fastest form this processor runs (both give the same bits).
inline void advance_coordinate(double* s, const double* f, const std::uint8_t* type,
                               const std::array<double, 2>& c, std::size_t first,
                               std::size_t last) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    advance_coordinate_avx2(s, f, type, c, first, last);
    return;
  }
#endif
  advance_coordinate_scalar(s, f, type, c, first, last);
}

inline void heun_predict(double* s, double* s0, double* slope, const double* f,
                         const std::uint8_t* type, const std::array<double, 2>& c, double dt,
                         std::size_t first, std::size_t last) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    heun_predict_avx2(s, s0, slope, f, type, c, dt, first, last);
    return;
  }
#endif
  heun_predict_scalar(s, s0, slope, f, type, c, dt, first, last);
}

inline void heun_correct(double* s, const double* s0, const double* slope, const double* f,
                         const std::uint8_t* type, const std::array<double, 2>& c, double half_dt,
                         std::size_t first, std::size_t last) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    heun_correct_avx2(s, s0, slope, f, type, c, half_dt, first, last);
    return;
  }
#endif
  heun_correct_scalar(s, s0, slope, f, type, c, half_dt, first, last);
}

inline void hermite_coordinate(double* out, const double* s0, const double* fn, const double* fn1,
                               const double* delta, const HermiteWeights& w, std::size_t first,
                               std::size_t last) {
#if defined(JAM_AVX2_FORMS)
  if (cpu_has_avx2()) {
    hermite_coordinate_avx2(out, s0, fn, fn1, delta, w, first, last);
    return;
  }
#endif
  hermite_coordinate_scalar(out, s0, fn, fn1, delta, w, first, last);
}

}  // namespace jam
