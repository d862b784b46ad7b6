// The scan of scaling fits (stats/fit_scan.cpp) and its representative: the slowest rate_max
// whose fit is of quality ok, a plateau said rather than required, a systematic error that is
// the largest distance of any fit of quality ok from it, and the paper's protocol labelled.
// What that error covers is measured on planted corrections to scaling.
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "stats/fit_scan.hpp"
#include "stats/papers_protocol.hpp"
#include "synthetic_scaling.hpp"

using namespace jam::stats;
using jam::test::plant_correction;
using jam::test::synthetic;
using jam::test::Truth;

namespace {

const std::vector<double> kSixRates = {-5.0, -5.5, -6.0, -6.5, -7.0, -7.5};
const RateClearance kAll{std::nullopt, "all rates"};

StatsOptions scan_options(std::vector<double> half_windows = {0.04}) {
  StatsOptions o;
  o.order = 3;
  o.half_windows = std::move(half_windows);
  return o;
}

/// The largest |beta - the representative's| over the scan's fits of quality ok.
double largest_distance(const FitScan& s) {
  double far = 0.0;
  for (const auto& row : s.rows)
    if (row.result && row.result->quality == "ok")
      far = std::max(far, std::abs(row.result->beta - s.representative()->beta));
  return far;
}

}  // namespace

// Six rates: rate_max 1e-5 ... 1e-6.5 (each fit sees >= 3 rates). The representative is the
// slowest rate_max of quality ok, whatever the faster fits say; the paper's protocol is the
// 10^-6.5 row of the narrowest window, labelled.
BOOST_AUTO_TEST_CASE(the_representative_is_the_slowest_fit_of_quality_ok) {
  const Truth t;
  const FitScan s =
      scan_fits(synthetic(t, 7, 10, 0.78, 0.90, 0.03, kSixRates), scan_options({0.05, 0.03}), kAll,
                "phi");
  BOOST_TEST_REQUIRE(s.rows.size() == 8u);  // 2 windows x 4 rate_max
  BOOST_TEST_REQUIRE(s.representative() != nullptr, s.failure);
  const ScanRow& chosen = s.rows[*s.chosen];
  BOOST_TEST(chosen.half_window == 0.03);
  std::size_t slowest_ok = s.rows.size();
  for (std::size_t k = 0; k < s.rows.size(); ++k)
    if (s.rows[k].half_window == 0.03 && s.rows[k].result && s.rows[k].result->quality == "ok")
      slowest_ok = k;
  BOOST_TEST(*s.chosen == slowest_ok);
  BOOST_TEST(s.reason.find("the slowest whose fit is of quality ok") != std::string::npos,
             s.reason);
  // The systematic error: the largest distance of a fit of quality ok from the representative.
  BOOST_TEST(s.systematic.beta == largest_distance(s), boost::test_tools::tolerance(1e-12));
  BOOST_TEST(s.systematic.beta > 0.0);
  BOOST_TEST(s.systematic.fits >= 2u);
  // The paper's protocol: the narrowest window at rate_max 10^-6.5, labelled.
  BOOST_TEST_REQUIRE(s.papers_protocol.has_value());
  BOOST_TEST(s.rows[*s.papers_protocol].half_window == 0.03);
  BOOST_TEST(std::log10(s.rows[*s.papers_protocol].rate_max) == -6.5,
             boost::test_tools::tolerance(1e-9));
  // Without a rate_max of 10^-6.5 there is no such row.
  BOOST_TEST(!scan_fits(synthetic(t, 7), scan_options(), kAll, "phi").papers_protocol);
}

// On the scaling form the fits agree: a plateau. With a strong correction planted at the
// fastest rate only, the fastest rate_max's fit moves away: no plateau, said with the fit that
// moves most, and the representative (the slowest) keeps its quality.
BOOST_AUTO_TEST_CASE(a_plateau_is_said_and_a_drift_is_named) {
  const Truth t;
  const FitScan flat = scan_fits(synthetic(t, 7), scan_options(), kAll, "phi");
  BOOST_TEST_REQUIRE(flat.representative() != nullptr, flat.failure);
  BOOST_TEST(flat.plateau, flat.reason);
  BOOST_TEST(flat.reason.find("a plateau") != std::string::npos, flat.reason);
  BOOST_TEST(flat.rows[*flat.chosen].rate_max == std::pow(10.0, -5.5));

  auto corrected = synthetic(t, 7);
  for (auto& row : corrected.front().pressure)
    for (std::size_t k = 0; k < row.size(); ++k)
      row[k] *= std::exp(6.0 * (corrected.front().phi[k] - t.phi_j));
  const FitScan bent = scan_fits(corrected, scan_options(), kAll, "phi");
  BOOST_TEST_REQUIRE(bent.representative() != nullptr, bent.failure);
  BOOST_TEST_MESSAGE("drift: " << bent.reason);
  BOOST_TEST(bent.rows[*bent.chosen].rate_max == std::pow(10.0, -5.5));
  BOOST_TEST(bent.representative()->quality == "ok", bent.representative()->quality_reason);
  if (bent.rows[0].result && bent.rows[0].result->quality == "ok") {
    BOOST_TEST(!bent.plateau, bent.reason);
    BOOST_TEST(bent.reason.find("no plateau") != std::string::npos, bent.reason);
  } else {
    // The fast fit fails its own quality test: nothing of quality ok left to compare.
    BOOST_TEST(bent.reason.find("plateau unknown") != std::string::npos, bent.reason);
  }

  // Three rates: one rate_max, nothing to compare it with.
  auto three = synthetic(t, 7);
  three.erase(three.begin());
  const FitScan single = scan_fits(three, scan_options(), kAll, "phi");
  BOOST_TEST_REQUIRE(single.representative() != nullptr, single.failure);
  BOOST_TEST(!single.plateau);
  BOOST_TEST(single.reason.find("plateau unknown") != std::string::npos, single.reason);
  BOOST_TEST(std::isnan(single.systematic.beta));
}

// No fit of quality ok (a window too narrow to hold enough points of every rate): the slowest
// fit with a result, flagged poor with the reason.
BOOST_AUTO_TEST_CASE(a_scan_without_a_fit_of_quality_ok_flags_its_representative_poor) {
  const Truth t;
  const FitScan s = scan_fits(synthetic(t, 7), scan_options({0.0015}), kAll, "phi");
  BOOST_TEST_REQUIRE(s.representative() != nullptr, s.failure);
  BOOST_TEST(s.representative()->quality == "poor");
  BOOST_TEST(s.reason.find("no fit of quality ok") != std::string::npos, s.reason);
}

// What the representative's error covers, measured. Each data set's pressure is the scaling
// form times exp(a (phi - phi_J)) = exp(a x rate^(1/z nu)), an analytic correction to scaling
// whose effect shrinks with the rate (the drift of an effective exponent, as paper-2d's beta
// drifts). +-2 sqrt(jackknife^2 + systematic^2) must cover the true beta in >= 27 of 30 sets
// (90%) with and without the correction, on a four-rate and a six-rate design, 3% noise. The
// jackknife alone does not (the correction is real): fewer than 27 of 30 with it.
// Measured when written (30 sets each): four rates 29/30 (a = 6), 30/30 (a = 0); six rates
// 30/30 and 30/30; the previous rule (the fastest confirmed rate_max, half the spread) 18/30
// and 21/30 with the correction.
BOOST_AUTO_TEST_CASE(the_error_covers_a_planted_correction_to_scaling) {
  const Truth t;
  for (const bool six : {false, true}) {
    for (const double a : {6.0, 0.0}) {
      int sets = 0, jackknife_only = 0, covered = 0;
      double bias = 0.0, total_err = 0.0;
      for (int k = 0; k < 30; ++k) {
        auto d = six ? synthetic(t, 500 + k, 10, 0.78, 0.90, 0.03, kSixRates)
                     : synthetic(t, 500 + k, 10, 0.78, 0.90, 0.03);
        plant_correction(d, a, t.phi_j);
        const FitScan s = scan_fits(d, scan_options({0.05, 0.03}), kAll, "phi");
        const ScalingFitResult* r = s.representative();
        BOOST_TEST_REQUIRE(r != nullptr, s.failure);
        ++sets;
        const double syst = std::isnan(s.systematic.beta) ? 0.0 : s.systematic.beta;
        const double miss = std::abs(r->beta - t.beta()), total = std::hypot(r->beta_err, syst);
        bias += (r->beta - t.beta()) / 30, total_err += total / 30;
        jackknife_only += miss <= 2 * r->beta_err;
        covered += miss <= 2 * total;
      }
      BOOST_TEST_MESSAGE((six ? "six" : "four")
                         << " rates, a " << a << ": mean bias of beta " << bias
                         << ", mean total error " << total_err
                         << "; +-2 sigma covers the truth: jackknife alone " << jackknife_only
                         << "/" << sets << ", with the systematic " << covered << "/" << sets);
      BOOST_TEST(covered >= 27, covered << " of " << sets);
      if (a > 0 && !six) BOOST_TEST(jackknife_only < 27, jackknife_only << " of " << sets);
    }
  }
}

namespace {

/// Two sizes of synthetic constant-phi averages (one truth, independent noise), as jam stats
/// holds them, at rates 1e-5 ... 10^-7.5.
CampaignStats two_sizes(const Truth& t) {
  CampaignStats s;
  s.fit_phi_init = 0.4;
  for (const std::int64_t n : {256, 1024}) {
    for (const FitEnsemble& f : synthetic(t, n, 10, 0.78, 0.90, 0.03, kSixRates)) {
      EnsembleStats e;
      e.key = {n, 0.4, std::log10(f.rate)};
      e.constant_phi.grid = f.phi;
      e.constant_phi.sample_ids = f.sample_ids;
      e.constant_phi.names = {"pressure"};
      e.constant_phi.tables = {f.pressure};
      s.ensembles.push_back(std::move(e));
    }
  }
  return s;
}

/// The options with the finite_size verdicts declared to the fit (fit_verdicts.hpp): one per
/// rate, 'p' pass, else fail; "" none declared.
StatsOptions with_verdicts(const std::string& statuses) {
  StatsOptions o;  // half windows 0.03, 0.02, 0.01
  if (statuses.empty()) return o;
  o.verdicts.files = "checks.json";
  o.verdicts.checks_json = true;
  const double rates[] = {-6.5, -7.0, -7.5};
  for (std::size_t k = 0; k < 3; ++k)
    o.verdicts.finite_size.push_back({0, 0.4, rates[k], statuses[k] == 'p', "checks.json"});
  return o;
}

}  // namespace

// The paper's protocol as a labelled fit (stats/papers_protocol.cpp): fifth order, rate_max
// 10^-6.5, the narrowest window; the sizes pooled only when the finite_size check's pooled
// verdicts at constant phi pass at every fitted rate, else the largest size alone, said so.
BOOST_AUTO_TEST_CASE(the_papers_protocol_pools_sizes_only_where_finite_size_allows) {
  const Truth t;
  const CampaignStats s = two_sizes(t);
  const auto alone = fit_papers_protocol(s, with_verdicts(""));
  BOOST_TEST_REQUIRE(alone.has_value());
  BOOST_TEST_REQUIRE(alone->result.has_value(), alone->failure);
  BOOST_TEST(alone->result->samples == 10u);
  BOOST_TEST(alone->how.find("the largest size alone (no finite_size verdicts") !=
                 std::string::npos,
             alone->how);
  BOOST_TEST(alone->row.half_window == 0.01);
  BOOST_TEST(std::log10(alone->row.rate_max) == -6.5, boost::test_tools::tolerance(1e-9));

  const auto pooled = fit_papers_protocol(s, with_verdicts("ppp"));
  BOOST_TEST_REQUIRE(pooled->result.has_value(), pooled->failure);
  BOOST_TEST(pooled->result->samples == 20u);  // both sizes' samples, kept apart
  BOOST_TEST(pooled->how.find("pooled: the finite_size check") != std::string::npos, pooled->how);
  BOOST_TEST(pooled->how.find("order 5") != std::string::npos, pooled->how);
  BOOST_TEST(std::abs(pooled->result->beta - t.beta()) < 3 * pooled->result->beta_err,
             pooled->result->beta << " +- " << pooled->result->beta_err);

  const auto refused = fit_papers_protocol(s, with_verdicts("pfp"));
  BOOST_TEST(refused->result->samples == 10u);
  BOOST_TEST(refused->how.find("does not pass at rate 1e-7") != std::string::npos, refused->how);

  // No rate at or below 10^-6.5: no such fit.
  CampaignStats fast = s;
  std::erase_if(fast.ensembles, [](const EnsembleStats& e) { return e.key.log10_rate < -6.0; });
  BOOST_TEST(!fit_papers_protocol(fast, with_verdicts("")).has_value());
}
