// The Lanczos estimate of the stiffest contact mode (sim/dynamics/stiffest_mode_estimate.hpp):
// exact on one contact (closed form, both contact laws), at or below and close to lambda_max of
// packings, against a dense eigensolver of the matrix assembled here by brute force over all
// pairs (not the neighbor list); and the Chebyshev integrator driven by it against the
// Gershgorin bound and a converged Heun reference from the same state; the packed form of
// the product's per-contact terms against the scalar one, bit for bit.
#include <Eigen/Eigenvalues>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "helpers.hpp"
#include "sim/dynamics/overdamped_chebyshev.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/dynamics/stiffest_mode_estimate.hpp"
#include "sim/model/hertzian_contact.hpp"

using namespace jam;

namespace {

/// lambda_max of W^-1/2 H_n W^-1/2 from a dense eigensolver, the matrix assembled over all
/// pairs (O(N^2)) with the minimum image and the contact law's own stiffness.
template <int D, class Contact>
double dense_lambda_max(const System<D, Contact>& sys, double box_length) {
  const std::size_t n = sys.size();
  Eigen::MatrixXd a =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(D * n), static_cast<Eigen::Index>(D * n));
  const auto& w = sys.species.drag;
  const auto& type = sys.particles.type;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      std::array<double, D> dr;
      double r2 = 0.0;
      for (int d = 0; d < D; ++d) {
        double ds = sys.particles.s[d][i] - sys.particles.s[d][j];
        ds -= std::round(ds);
        dr[d] = box_length * ds;
        r2 += dr[d] * dr[d];
      }
      const int pair = type[i] + type[j];
      if (!sys.contact.in_contact(r2, pair) || r2 == 0.0) continue;
      const double k = sys.contact.radial_stiffness(r2, pair);
      const double si = 1.0 / std::sqrt(w[type[i]]), sj = 1.0 / std::sqrt(w[type[j]]);
      for (int p = 0; p < D; ++p) {
        for (int q = 0; q < D; ++q) {
          const double block = k * dr[p] * dr[q] / r2;
          const auto ip = static_cast<Eigen::Index>(D * i + p),
                     iq = static_cast<Eigen::Index>(D * i + q);
          const auto jp = static_cast<Eigen::Index>(D * j + p),
                     jq = static_cast<Eigen::Index>(D * j + q);
          a(ip, iq) += si * si * block;
          a(jp, jq) += sj * sj * block;
          a(ip, jq) -= si * sj * block;
          a(jp, iq) -= si * sj * block;
        }
      }
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(a, Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff();
}

}  // namespace

// One small and one big particle in contact: the one non-zero eigenvalue is the radial mode,
// lambda = k (1/gamma_s + 1/gamma_b) with k = U''(r) (1/d_sb^2 for the harmonic law, (3/2)
// delta^(1/2) / d_sb^2 for the Hertzian one). Lanczos meets the invariant subspace at its first
// step and is exact to round-off.
BOOST_AUTO_TEST_CASE(one_contact_in_closed_form) {
  const double d_sb = 1.2;  // (1 + 1.4) / 2
  for (double r : {1.0, 1.15}) {
    {
      auto sys = test::make_system<2>({{{0.0, 0.0}}, {{r, 0.0}}}, {0, 1}, 10.0);
      sys.compute_elastic_forces(10.0);
      const auto& w = sys.species.drag;
      const double lambda = (1.0 / (d_sb * d_sb)) * (1.0 / w[0] + 1.0 / w[1]);
      BOOST_TEST(StiffestModeEstimate<2>().estimate(sys, 10.0, w) == lambda,
                 boost::test_tools::tolerance(1e-12));
    }
    {
      auto sys = test::make_system<3>({{{0.0, 0.0, 0.0}}, {{0.0, r, 0.0}}}, {0, 1}, 10.0);
      sys.compute_elastic_forces(10.0);
      const auto& w = sys.species.drag;
      const double lambda = (1.0 / (d_sb * d_sb)) * (1.0 / w[0] + 1.0 / w[1]);
      BOOST_TEST(StiffestModeEstimate<3>().estimate(sys, 10.0, w) == lambda,
                 boost::test_tools::tolerance(1e-12));
    }
    {
      auto sys = test::make_system<2, HertzianContact>({{{0.0, 0.0}}, {{r, 0.0}}}, {0, 1}, 10.0);
      sys.compute_elastic_forces(10.0);
      const auto& w = sys.species.drag;
      const double k = 1.5 * std::sqrt(1.0 - r / d_sb) / (d_sb * d_sb);
      BOOST_TEST(StiffestModeEstimate<2>().estimate(sys, 10.0, w) == k * (1.0 / w[0] + 1.0 / w[1]),
                 boost::test_tools::tolerance(1e-12));
    }
  }
  // No contact: nothing to estimate.
  auto apart = test::make_system<2>({{{0.0, 0.0}}, {{3.0, 0.0}}}, {0, 1}, 10.0);
  apart.compute_elastic_forces(10.0);
  BOOST_TEST(StiffestModeEstimate<2>().estimate(apart, 10.0, apart.species.drag) == 0.0);
}

// Random packings well above jamming (many contacts, every overlap): the estimate is a Ritz
// value, so at or below lambda_max (to round-off), and after 30 Lanczos steps within 3% of it
// (measured: see the message; the integrator's safety factor is 1.2); the Gershgorin bound lies
// above both.
template <int D>
void check_packing(double phi, std::uint64_t seed) {
  auto sys = test::random_system<D>(D == 2 ? 200 : 150, phi, seed);
  const double length = sys.box.length(0.0);
  sys.compute_elastic_forces(length);
  const double exact = dense_lambda_max(sys, length);
  StiffestModeEstimate<D> estimator;
  const double estimate = estimator.estimate(sys, length, sys.species.drag);
  const double bound = stiffest_mode_bound(sys, length, sys.species.drag);
  BOOST_TEST_MESSAGE(D << "D phi " << phi << ": " << estimator.contacts() << " contacts, estimate "
                       << estimate << ", lambda_max " << exact << ", bound " << bound);
  BOOST_TEST(estimator.contacts() > sys.size());
  BOOST_TEST(estimate <= exact * (1.0 + 1e-10));
  BOOST_TEST(estimate >= 0.97 * exact);
  BOOST_TEST(bound >= exact);
}

BOOST_AUTO_TEST_CASE(packings_against_a_dense_eigensolver) {
  for (std::uint64_t seed : {1, 2, 3}) {
    check_packing<2>(0.86, seed);
    check_packing<2>(0.95, seed);
    check_packing<3>(0.70, seed);
  }
}

// The same compression integrated with lambda_max from the estimate and from the bound, from a
// relaxed state at phi 0.84 at rate 1e-5 for 2000 t0 (2D, N = 256), against Heun at dt 0.02
// (far inside its stability bound 2 / lambda_max ~ 0.4; its own error ~ dt^2). Both Chebyshev
// runs keep every particle within 1e-3 d_s of the reference (each step's local error is held
// at 1e-4 d_s and the overdamped dynamics contracts it), and the estimate takes fewer stages.
BOOST_AUTO_TEST_CASE(integrator_with_the_estimate) {
  auto start = test::random_system<2>(256, 0.84, 7);
  {
    OverdampedChebyshev<2> relax(start.size(), 1e-4, 0.1);
    double t = 0.0;
    for (int k = 0; k < 400; ++k) t += relax.step(start, t, 1e9);
  }
  const double rate = 1e-5, t_end = 2000.0;
  auto compress = [&](auto& stepper, auto& sys) {
    sys.box.compression_rate = rate;
    double t = 0.0;
    while (t < t_end) t += stepper.step(sys, t, t_end - t);
  };
  auto reference = start;
  OverdampedHeun<2> heun(reference.size(), StepperOptions{});
  reference.box.compression_rate = rate;
  for (double t = 0.0; t < t_end - 1e-9; t += 0.02) heun.step(reference, t, 0.02);

  std::array<std::uint64_t, 2> stages{};
  for (bool estimate : {true, false}) {
    auto sys = start;
    OverdampedChebyshev<2> cheb(sys.size(), 1e-4, 0.1);
    cheb.set_stiffest_mode_estimate(estimate);
    compress(cheb, sys);
    double worst = 0.0;
    for (std::size_t i = 0; i < sys.size(); ++i) {
      double d2 = 0.0;
      for (int d = 0; d < 2; ++d) {
        double ds = sys.particles.s[d][i] - reference.particles.s[d][i];
        ds -= std::round(ds);
        d2 += ds * ds;
      }
      worst = std::max(worst, std::sqrt(d2) * sys.box.length(t_end));
    }
    stages[estimate ? 0 : 1] = cheb.stats().stages;
    BOOST_TEST_MESSAGE((estimate ? "estimate" : "bound")
                       << ": " << cheb.stats().stages << " stages, " << cheb.stats().rejections
                       << " rejected, worst " << worst);
    BOOST_TEST(worst < 1e-3);
    if (estimate) BOOST_TEST(cheb.stats().estimates > 0u);
  }
  BOOST_TEST(stages[0] < 0.9 * stages[1]);
}

// The per-contact terms of A x (sim/dynamics/mode_product_terms.hpp): the AVX2 form gives the
// scalar form's bits on every block, in 2D and 3D, with a last block that is not a multiple of
// four, on terms of both signs and widely different sizes (the forms must not reassociate).
template <int D>
void check_mode_term_forms(std::uint32_t contacts, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::uint32_t n = 97;
  std::vector<std::uint32_t> ci(contacts), cj(contacts);
  std::vector<double> ai(contacts), aj(contacts);
  std::array<std::vector<double>, D> g, x;
  for (int d = 0; d < D; ++d) g[d].resize(contacts), x[d].resize(n);
  for (std::uint32_t c = 0; c < contacts; ++c) {
    ci[c] = static_cast<std::uint32_t>(rng() % n);
    cj[c] = static_cast<std::uint32_t>(rng() % n);
    ai[c] = 1.0 + u(rng), aj[c] = 0.5 + u(rng);
    for (int d = 0; d < D; ++d) g[d][c] = u(rng) * std::pow(10.0, 4.0 * u(rng));
  }
  for (int d = 0; d < D; ++d)
    for (double& e : x[d]) e = u(rng);
  ModeProductInput<D> in{
      .ci = ci.data(), .cj = cj.data(), .ai = ai.data(), .aj = aj.data(), .g = {}, .x = {}};
  for (int d = 0; d < D; ++d) in.g[d] = g[d].data(), in.x[d] = x[d].data();
  BOOST_TEST_REQUIRE(contacts % kModeBlockContacts % 4 != 0u);
  for (std::uint32_t c0 = 0; c0 < contacts; c0 += kModeBlockContacts) {
    const std::uint32_t c1 = std::min(contacts, c0 + kModeBlockContacts);
    ModeTermsBlock<D> scalar{}, dispatched{};
    mode_terms_scalar(in, c0, c1, scalar);
    mode_terms(in, c0, c1, dispatched);
    BOOST_TEST(std::memcmp(&scalar, &dispatched, sizeof scalar) == 0);
    // Something was computed: the terms of the block's first contact, by hand.
    double p = 0.0;
    for (int d = 0; d < D; ++d) p += g[d][c0] * (ai[c0] * x[d][ci[c0]] - aj[c0] * x[d][cj[c0]]);
    BOOST_TEST(scalar.to_i[0][0] == ai[c0] * p * g[0][c0]);
    BOOST_TEST(scalar.to_j[D - 1][0] == aj[c0] * p * g[D - 1][c0]);
  }
}

BOOST_AUTO_TEST_CASE(mode_product_term_forms_give_the_same_bits) {
  check_mode_term_forms<2>(3 * kModeBlockContacts + 7, 11);
  check_mode_term_forms<3>(2 * kModeBlockContacts + 5, 12);
}
