// Jackknife errors and bias correction against closed forms; averages at constant phi and at
// constant Z on runs whose curves are known exactly; the shrunk covariance.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "stats/averages.hpp"
#include "stats/covariance.hpp"
#include "stats/jackknife.hpp"
#include "stats/sample_average.hpp"

using namespace jam::stats;

BOOST_AUTO_TEST_CASE(jackknife_of_a_mean_is_the_standard_error) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g(3.0, 2.0);
  std::vector<std::vector<double>> table(12, std::vector<double>(1));
  SampleAccumulator acc;
  for (auto& row : table) {
    row[0] = g(rng);
    acc.add(row[0]);
  }
  const auto j = jackknife(table.size(), [&](std::size_t k) { return column_means(table, k); });
  const SampleMean m = acc.finalize();
  // Identities: for a linear function the jackknife estimate is the mean and its error the
  // standard error, exactly (up to round-off).
  BOOST_TEST(j.estimate[0] == m.mean, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(j.error[0] == m.error, boost::test_tools::tolerance(1e-13));
}

BOOST_AUTO_TEST_CASE(jackknife_removes_the_bias_of_a_square) {
  // f = (mean)^2 has bias sigma^2/S; the jackknife-corrected estimate is exactly
  // mean^2 - s^2/S (s^2 the unbiased sample variance), an unbiased estimate of mu^2.
  std::mt19937_64 rng(2);
  std::normal_distribution<double> g(0.5, 1.0);
  const std::size_t s = 8;
  double corrected_sum = 0.0, plain_sum = 0.0;
  const int trials = 20000;
  for (int t = 0; t < trials; ++t) {
    std::vector<std::vector<double>> table(s, std::vector<double>(1));
    SampleAccumulator acc;
    for (auto& row : table) acc.add(row[0] = g(rng));
    const auto j = jackknife(s, [&](std::size_t k) {
      const double m = column_means(table, k)[0];
      return std::vector<double>{m * m};
    });
    const SampleMean m = acc.finalize();
    const double s2 = m.error * m.error * s;  // unbiased variance
    BOOST_TEST(j.estimate[0] == m.mean * m.mean - s2 / s, boost::test_tools::tolerance(1e-10));
    corrected_sum += j.estimate[0];
    plain_sum += j.plain[0];
  }
  // mu^2 = 0.25; the plain estimate is high by sigma^2/S = 0.125. Standard error of the
  // average over 20000 trials is about 0.003: 0.015 is five of them.
  BOOST_TEST(std::abs(corrected_sum / trials - 0.25) < 0.015);
  BOOST_TEST(std::abs(plain_sum / trials - 0.375) < 0.015);
}

namespace {
// A run whose curves are known: Z = z0 + 20 (phi - 0.80), p = exp(40 (phi - 0.84)) + offset,
// output points at irregular packings.
RunCurves known_run(std::int64_t sample, double z0, double offset) {
  RunCurves r;
  r.sample = sample;
  for (double phi = 0.7503 + 0.0001 * sample; phi < 0.86; phi += 0.00237) {
    r.phi.push_back(phi);
    r.contacts.push_back(z0 + 20.0 * (phi - 0.80));
    r.pressure.push_back(std::exp(40.0 * (phi - 0.84)) + offset);
  }
  return r;
}
}  // namespace

BOOST_AUTO_TEST_CASE(constant_phi_average_interpolates_and_averages) {
  const std::vector<RunCurves> runs = {known_run(0, 3.0, 0.0), known_run(1, 3.2, 0.02),
                                       known_run(2, 3.4, 0.04)};
  const GridAverage a = average_at_constant_phi(runs, 0.001);
  BOOST_TEST(a.grid.front() >= 0.7505);
  BOOST_TEST(a.grid.back() <= runs[0].phi.back());
  const auto& z = a.mean("contacts_per_particle");
  const auto& p = a.mean("pressure");
  for (std::size_t k = 0; k < a.grid.size(); ++k) {
    // Z is linear: interpolation exact; mean of the three offsets 3.0, 3.2, 3.4 is 3.2.
    BOOST_TEST(z[k].mean == 3.2 + 20.0 * (a.grid[k] - 0.80), boost::test_tools::tolerance(1e-12));
    // Standard error of {3.0, 3.2, 3.4}: sd 0.2, / sqrt(3).
    BOOST_TEST(z[k].error == 0.2 / std::sqrt(3.0), boost::test_tools::tolerance(1e-9));
    // p is convex: linear interpolation over steps of 0.00237 is within (40 h)^2/8 relative.
    const double exact = std::exp(40.0 * (a.grid[k] - 0.84)) + 0.02;
    BOOST_TEST(std::abs(p[k].mean - exact) <= 1.2e-3 * exact);
  }
}

BOOST_AUTO_TEST_CASE(constant_z_average_recovers_phi_of_z_and_p_of_z) {
  const std::vector<RunCurves> runs = {known_run(0, 3.0, 0.0), known_run(1, 3.2, 0.0),
                                       known_run(2, 3.4, 0.0)};
  const GridAverage a = average_at_constant_z(runs, 0.01, false);
  BOOST_TEST_REQUIRE(a.grid.size() > 100u);
  const auto& phi = a.mean("packing_fraction");
  const auto& p = a.mean("pressure");
  for (std::size_t k = 0; k < a.grid.size(); ++k) {
    // phi(Z) = 0.80 + (Z - z0)/20 for each run; the mean over z0 = 3.0, 3.2, 3.4.
    const double expected_phi = 0.80 + (a.grid[k] - 3.2) / 20.0;
    BOOST_TEST(phi[k].mean == expected_phi, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(phi[k].error == (0.2 / 20.0) / std::sqrt(3.0), boost::test_tools::tolerance(1e-9));
    double expected_p = 0.0;
    for (double z0 : {3.0, 3.2, 3.4})
      expected_p += std::exp(40.0 * (0.80 + (a.grid[k] - z0) / 20.0 - 0.84)) / 3.0;
    BOOST_TEST(std::abs(p[k].mean - expected_p) <= 1.2e-3 * expected_p);
  }
  BOOST_CHECK_THROW(average_at_constant_z(runs, 0.01, true), std::invalid_argument);
}

// A run whose first contacts_per_particle is absurd but finite (1e300, or 4.0 with one
// exponent bit flipped: 5.4e154): a one-line error, no grid of any size (it used to overflow
// the grid's index and grow until the memory ran out).
BOOST_AUTO_TEST_CASE(absurd_contact_numbers_are_an_error_not_a_huge_grid) {
  double flipped = 4.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &flipped, sizeof bits);
  bits ^= std::uint64_t{1} << 61;  // an exponent bit
  std::memcpy(&flipped, &bits, sizeof bits);
  BOOST_TEST_REQUIRE(flipped > 1e150);
  for (double absurd : {1e300, flipped}) {
    // One run's first value only: the common range is then [absurd, a normal Z], whose point
    // count is negative and passed the count bound before the index check.
    std::vector<RunCurves> runs = {known_run(0, 3.0, 0.0), known_run(1, 3.2, 0.0)};
    runs[0].contacts.front() = absurd;
    BOOST_CHECK_EXCEPTION(average_at_constant_z(runs, 0.01, false), std::runtime_error,
                          [](const std::runtime_error& e) {
                            return std::string(e.what()).find("beyond any packing") !=
                                   std::string::npos;
                          });
  }
}

// A step whose grid over the runs' common range has more than 10^6 points (a damaged
// phi_step: 1e-8 over [0.7505, 0.857] is about 1.07e7 points) is refused by its count, before
// any of it is allocated (campaign/grid_limit.hpp); 1e-6 over the same range (1.07e5) is not.
BOOST_AUTO_TEST_CASE(an_averaging_grid_beyond_a_million_points_is_refused) {
  const std::vector<RunCurves> runs = {known_run(0, 3.0, 0.0), known_run(1, 3.2, 0.0)};
  BOOST_CHECK_EXCEPTION(average_at_constant_phi(runs, 1e-8), std::runtime_error,
                        [](const std::runtime_error& e) {
                          return std::string(e.what()).find("points (at most 1e+06)") !=
                                 std::string::npos;
                        });
  BOOST_TEST(average_at_constant_phi(runs, 1e-6).grid.size() > 100000u);
}

BOOST_AUTO_TEST_CASE(first_crossing_when_z_is_not_monotonic) {
  RunCurves r;
  r.phi = {0.80, 0.81, 0.82, 0.83, 0.84};
  r.contacts = {3.0, 3.6, 3.2, 3.8, 4.0};  // reaches 3.5 first between 0.80 and 0.81
  r.pressure = {1.0, 2.0, 3.0, 4.0, 5.0};
  const GridAverage a = average_at_constant_z({r, r}, 0.5, false);
  BOOST_TEST_REQUIRE(a.grid.size() == 2u);  // 3.5 and 4.0
  BOOST_TEST(a.mean("packing_fraction")[0].mean == 0.80 + 0.01 * (0.5 / 0.6),
             boost::test_tools::tolerance(1e-12));
  BOOST_TEST(a.mean("packing_fraction")[1].mean == 0.84, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(shrunk_covariance_and_chi2) {
  // Strongly correlated points (a common offset per sample): the shrinkage stays small and
  // chi^2 of a residual along the common mode is far below its diagonal value.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> dev(30, std::vector<double>(5));
  for (auto& row : dev) {
    const double common = g(rng);
    for (double& x : row) x = common + 0.1 * g(rng);
  }
  const ShrunkCovariance c = shrunk_covariance_of_mean(dev);
  BOOST_TEST(c.lambda < 0.2);
  const std::vector<double> r(5, 0.2);
  double diag = 0.0;
  for (std::size_t i = 0; i < 5; ++i) diag += r[i] * r[i] / c.matrix[i][i];
  BOOST_TEST(chi2_with_covariance(r, c) < 0.4 * diag);
  // Independent points: the sample correlations are noise and are shrunk hard.
  for (auto& row : dev)
    for (double& x : row) x = g(rng);
  BOOST_TEST(shrunk_covariance_of_mean(dev).lambda > 0.5);
}

BOOST_AUTO_TEST_CASE(interpolation_and_grouping) {
  const std::vector<double> x = {0.1, 0.2, 0.4}, y = {1.0, 3.0, 7.0};
  BOOST_TEST(interpolate(x, y, 0.1) == 1.0);
  BOOST_TEST(interpolate(x, y, 0.3) == 5.0, boost::test_tools::tolerance(1e-14));
  BOOST_TEST(interpolate(x, y, 0.4) == 7.0);
  BOOST_TEST(std::isnan(interpolate(x, y, 0.41)));
  BOOST_TEST(std::isnan(interpolate(x, y, 0.09)));
  RunCurves a, b, c;
  a.n = 64, b.n = 128, c.n = 64;
  a.log10_rate = b.log10_rate = -3;
  c.log10_rate = -4;
  const Ensembles separate = group_runs({a, b, c}, false);
  BOOST_TEST(separate.size() == 3u);
  const Ensembles pooled = group_runs({a, b, c}, true);
  BOOST_TEST(pooled.size() == 2u);
  BOOST_TEST(pooled.at(EnsembleKey{0, 0.0, -3}).size() == 2u);
}
