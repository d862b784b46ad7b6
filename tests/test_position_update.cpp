// The overdamped position updates (Euler's step, Heun's two stages): the AVX2 forms (and the
// dispatched ones) give the one-particle forms' bits, including particles that cross the periodic
// boundary in either direction, land exactly on 1, or are NaN, at every tail length; and the
// one-particle form wraps into [0, 1). The same for the Chebyshev step's continuous extension.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sim/dynamics/position_update.hpp"

using namespace jam;

namespace {

struct Case {
  std::vector<double> s, f;
  std::vector<std::uint8_t> type;
};

/// n particles, most moving a little, some pushed across 0 or 1, some exactly onto 1 or a hair
/// below 0, one NaN force.
Case make_case(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), small(-1e-3, 1e-3);
  Case c;
  for (std::size_t i = 0; i < n; ++i) {
    c.s.push_back(unit(rng));
    c.type.push_back(static_cast<std::uint8_t>(rng() % 2));
    double f = small(rng);
    if (i % 7 == 3) f = (c.s[i] < 0.5 ? -1.5 : 1.5) * c.s[i];  // crosses a boundary
    c.f.push_back(f);
  }
  if (n > 5) {
    c.s[5] = 0.75;
    c.f[5] = 0.25 / 0.5;  // c = 0.5 for small particles below: lands exactly on 1
    c.type[5] = kSmall;
  }
  if (n > 9) {
    c.s[9] = 0.0;
    c.f[9] = -1e-300;  // a hair below 0
  }
  if (n > 2) c.f[2] = std::numeric_limits<double>::quiet_NaN();
  return c;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  // (memcmp must not be handed the null data() of empty vectors)
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace

BOOST_AUTO_TEST_CASE(vector_forms_give_the_scalar_bits) {
  const std::array<double, 2> c = {0.5, 0.35};
  for (std::size_t n : {0, 1, 3, 4, 5, 7, 8, 64, 1001}) {
    const Case base = make_case(n, 11 + n);
    for (std::size_t first : {std::size_t{0}, std::size_t{1}, n / 2}) {
      if (first > n) continue;
      auto reference = base.s;
      advance_coordinate_scalar(reference.data(), base.f.data(), base.type.data(), c, first, n);
      auto dispatched = base.s;
      advance_coordinate(dispatched.data(), base.f.data(), base.type.data(), c, first, n);
      BOOST_TEST(same_bits(dispatched, reference), "n " << n << " first " << first);
#if defined(JAM_AVX2_FORMS)
      if (cpu_has_avx2()) {
        auto avx2 = base.s;
        advance_coordinate_avx2(avx2.data(), base.f.data(), base.type.data(), c, first, n);
        BOOST_TEST(same_bits(avx2, reference), "n " << n << " first " << first);
      }
#endif
    }
  }
}

BOOST_AUTO_TEST_CASE(heun_stages_give_the_scalar_bits) {
  const std::array<double, 2> c0 = {0.5, 0.35}, c1 = {0.49, 0.36};
  const double dt = 0.9, half_dt = 0.45;
  for (std::size_t n : {0, 1, 3, 4, 5, 7, 8, 64, 1001}) {
    const Case base = make_case(n, 29 + n);
    const Case second = make_case(n, 31 + n);  // the forces at the predicted positions
    for (std::size_t first : {std::size_t{0}, std::size_t{1}, n / 2}) {
      // Reference: both stages one particle at a time.
      auto s = base.s;
      std::vector<double> s0(n, -7.0), slope(n, -7.0);
      heun_predict_scalar(s.data(), s0.data(), slope.data(), base.f.data(), base.type.data(), c0,
                          dt, first, n);
      const auto predicted = s;
      heun_correct_scalar(s.data(), s0.data(), slope.data(), second.f.data(), base.type.data(), c1,
                          half_dt, first, n);
      const auto corrected = s;
      using Predict = void (*)(double*, double*, double*, const double*, const std::uint8_t*,
                               const std::array<double, 2>&, double, std::size_t, std::size_t);
      using Correct =
          void (*)(double*, const double*, const double*, const double*, const std::uint8_t*,
                   const std::array<double, 2>&, double, std::size_t, std::size_t);
      std::vector<std::pair<Predict, Correct>> forms{{heun_predict, heun_correct}};
#if defined(JAM_AVX2_FORMS)
      if (cpu_has_avx2()) forms.emplace_back(heun_predict_avx2, heun_correct_avx2);
#endif
      for (auto [predict, correct] : forms) {
        auto t = base.s;
        std::vector<double> t0(n, -7.0), tslope(n, -7.0);
        predict(t.data(), t0.data(), tslope.data(), base.f.data(), base.type.data(), c0, dt, first,
                n);
        BOOST_TEST(same_bits(t, predicted), "predict n " << n << " first " << first);
        BOOST_TEST(same_bits(t0, s0));
        BOOST_TEST(same_bits(tslope, slope));
        correct(t.data(), t0.data(), tslope.data(), second.f.data(), base.type.data(), c1, half_dt,
                first, n);
        BOOST_TEST(same_bits(t, corrected), "correct n " << n << " first " << first);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(hermite_extension_gives_the_scalar_bits) {
  // The continuous extension at a few theta, its ends included: slopes and displacements from
  // the cases above (boundary crossings, a NaN), the same bits in every form.
  for (std::size_t n : {0, 1, 3, 4, 5, 7, 8, 64, 1001}) {
    const Case base = make_case(n, 37 + n), ends = make_case(n, 41 + n);
    std::vector<double> delta(n);
    for (std::size_t i = 0; i < n; ++i) delta[i] = 0.3 * base.f[i] + 0.7 * ends.f[i];
    for (double theta : {0.0, 0.25, 0.6180339887, 1.0}) {
      const double h = 0.9;
      const HermiteWeights w{h, theta * h, theta * theta, theta * theta * theta};
      for (std::size_t first : {std::size_t{0}, std::size_t{1}, n / 2}) {
        if (first > n) continue;
        std::vector<double> reference(n, -7.0), dispatched(n, -7.0);
        hermite_coordinate_scalar(reference.data(), base.s.data(), base.f.data(), ends.f.data(),
                                  delta.data(), w, first, n);
        hermite_coordinate(dispatched.data(), base.s.data(), base.f.data(), ends.f.data(),
                           delta.data(), w, first, n);
        BOOST_TEST(same_bits(dispatched, reference), "n " << n << " theta " << theta);
#if defined(JAM_AVX2_FORMS)
        if (cpu_has_avx2()) {
          std::vector<double> avx2(n, -7.0);
          hermite_coordinate_avx2(avx2.data(), base.s.data(), base.f.data(), ends.f.data(),
                                  delta.data(), w, first, n);
          BOOST_TEST(same_bits(avx2, reference), "n " << n << " theta " << theta);
        }
#endif
        for (std::size_t i = first; i < n; ++i) {
          if (std::isnan(reference[i])) continue;
          BOOST_TEST((reference[i] >= 0.0 && reference[i] < 1.0), i << ": " << reference[i]);
        }
        if (theta == 0.0 && first == 0 && n > 0) BOOST_TEST(reference[0] == base.s[0]);  // y(0) = 0
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(the_scalar_form_wraps_into_the_unit_interval) {
  const Case base = make_case(1001, 3);
  const std::array<double, 2> c = {0.5, 0.35};
  auto s = base.s;
  advance_coordinate_scalar(s.data(), base.f.data(), base.type.data(), c, 0, s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (std::isnan(base.f[i])) {
      BOOST_TEST(std::isnan(s[i]));
      continue;
    }
    BOOST_TEST((s[i] >= 0.0 && s[i] < 1.0), "i " << i << " s " << s[i]);
    // Against the unwrapped sum modulo 1 (exact to a few ulp of 1; a value that rounds onto
    // 1 wraps to 0).
    const double x = base.s[i] + c[base.type[i]] * base.f[i];
    double expected = x - std::floor(x);
    if (expected >= 1.0) expected = 0.0;
    BOOST_TEST(std::abs(s[i] - expected) <= 4e-16, "i " << i);
  }
  BOOST_TEST(s[5] == 0.0);  // exactly onto 1 wraps to 0
}
