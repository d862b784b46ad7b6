// The integrators' cost model (sim/dynamics/integrator_cost.hpp), which `jam campaign plan`
// and the per-run limits rest on: its integral over a compression against the closed form.
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "sim/dynamics/integrator_cost.hpp"

namespace tt = boost::test_tools;
using jam::chebyshev_packing_factor;
using jam::compression_force_evaluations;
using jam::force_evaluations_per_time;

// Fixed steps: evaluations per step / dt over the whole time ln(phi_to / phi_from) / (D rate).
BOOST_AUTO_TEST_CASE(fixed_steps_cost_their_evaluations_over_the_time) {
  const double time = std::log(0.86 / 0.40) / (2 * 1e-4);
  BOOST_TEST(compression_force_evaluations("heun", 2, 0.1, 1e-4, 1e-4, false, 1024, 0.40, 0.86) ==
                 20.0 * time,
             tt::tolerance(1e-12));
  BOOST_TEST(compression_force_evaluations("euler", 3, 0.01, 1e-4, 1e-4, false, 1024, 0.40, 0.66) ==
                 100.0 * std::log(0.66 / 0.40) / (3 * 1e-4),
             tt::tolerance(1e-12));
}

// The packing factor is 1 from the cost packing on and (phi / packing)^k below it, with k
// growing as the rate falls (slow runs are cheapest far below jamming).
BOOST_AUTO_TEST_CASE(the_packing_factor_is_one_near_jamming_and_falls_below) {
  for (int dim : {2, 3}) {
    const jam::ChebyshevCost& c = jam::chebyshev_cost(dim);
    BOOST_TEST(chebyshev_packing_factor(dim, c.packing, 1e-6) == 1.0);
    BOOST_TEST(chebyshev_packing_factor(dim, c.packing + 0.03, 1e-6) == 1.0);
    BOOST_TEST(chebyshev_packing_factor(dim, 0.5 * c.packing, 1e-6) == std::pow(0.5, c.exponent),
               tt::tolerance(1e-12));
    BOOST_TEST(chebyshev_packing_factor(dim, 0.5 * c.packing, 1e-8) <
               chebyshev_packing_factor(dim, 0.5 * c.packing, 1e-4));
  }
  BOOST_TEST(chebyshev_packing_factor(2, 0.425, 1e-4) == std::pow(0.5, 1.35), tt::tolerance(1e-12));
  BOOST_TEST(chebyshev_packing_factor(3, 0.325, 1e-12) == std::pow(0.5, 4.5),
             tt::tolerance(1e-12));  // k capped
}

// The adaptive integrator's evaluations are the near-jamming rate times the time weighed by the
// factor: in closed form, with u = ln phi and k fixed, the integral of (phi / ref)^k du / (D
// rate) is ((phi_to / ref)^k - (phi_from / ref)^k) / (k D rate) below ref, plus the plain time
// above it. 64 trapezoids in ln phi: within 1e-3 of it (the integrand's curvature, k^2 / 12 /
// 64^2 of its range, bounds the error).
BOOST_AUTO_TEST_CASE(the_adaptive_cost_integrates_the_factor_in_closed_form) {
  const double rate = 1e-6, tolerance = 1e-5, n = 32768, k = 2.35;
  const double top = force_evaluations_per_time("chebyshev", 2, 0.1, rate, tolerance, true, n);
  const double ref = jam::chebyshev_cost(2).packing;
  const double below = (1.0 - std::pow(0.40 / ref, k)) / (k * 2 * rate);
  BOOST_TEST(compression_force_evaluations("chebyshev", 2, 0.1, rate, tolerance, true, n, 0.40,
                                           ref) == top * below,
             tt::tolerance(1e-3));
  const double above = std::log(0.88 / ref) / (2 * rate);
  BOOST_TEST(compression_force_evaluations("chebyshev", 2, 0.1, rate, tolerance, true, n, ref,
                                           0.88) == top * above,
             tt::tolerance(1e-12));
  // Across ref: the sum of the two (the kink costs a little more than 1e-3).
  BOOST_TEST(compression_force_evaluations("chebyshev", 2, 0.1, rate, tolerance, true, n, 0.40,
                                           0.88) == top * (below + above),
             tt::tolerance(3e-3));
}

// The near-jamming rate: (rate / 1e-6)^0.25 (tolerance / 1e-4)^-0.25 (N / 4096)^0.12 around
// 2.1 per t0, and rms at a tenth of max's tolerance kRmsEvaluationGain cheaper.
BOOST_AUTO_TEST_CASE(the_near_jamming_rate_scales_as_fitted) {
  const auto e = [](double rate, double tol, bool rms, double n) {
    return force_evaluations_per_time("chebyshev", 2, 0.1, rate, tol, rms, n);
  };
  BOOST_TEST(e(1e-6, 1e-4, false, 4096) == 2.1, tt::tolerance(1e-12));
  BOOST_TEST(force_evaluations_per_time("chebyshev", 3, 0.1, 1e-6, 1e-4, false, 4096) == 3.4,
             tt::tolerance(1e-12));
  BOOST_TEST(e(1e-4, 1e-4, false, 4096) / e(1e-6, 1e-4, false, 4096) == std::sqrt(10.0),
             tt::tolerance(1e-12));
  BOOST_TEST(e(1e-6, 1e-2, false, 4096) / e(1e-6, 1e-4, false, 4096) == 1 / std::sqrt(10.0),
             tt::tolerance(1e-12));
  BOOST_TEST(e(1e-6, 1e-4, false, 4096 * 32) / e(1e-6, 1e-4, false, 4096) == std::pow(32, 0.12),
             tt::tolerance(1e-12));
  BOOST_TEST(e(1e-6, 1e-4, false, 4096) / e(1e-6, 1e-5, true, 4096) == jam::kRmsEvaluationGain,
             tt::tolerance(1e-12));
}
