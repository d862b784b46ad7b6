// Verdicts by region (checks/regions.hpp): a size effect confined below jamming fails the region
// below and no other, where a pooled verdict over the fit's window lets the points near and
// above phi_J, which weigh most, hide it; and with nothing planted the regions add no false
// alarms beyond the check's alpha (Bonferroni over comparisons and regions). The data:
// synthetic_runs.hpp, 60 points at 0.001 from phi 0.80, phi_J 0.84 as a fit would give it.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/checks.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/verdict_file.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

constexpr double kPhiJ = 0.84;

/// Runs whose pressure is `factor` times the base below phi_J - 0.004 only.
std::vector<std::vector<double>> below_only(std::vector<std::vector<double>> p, double factor) {
  for (auto& row : p)
    for (std::size_t k = 0; k < row.size(); ++k)
      if (0.80 + 0.001 * static_cast<double>(k) < kPhiJ - 0.004 - 1e-9) row[k] *= factor;
  return p;
}

/// Two sizes at `rates` rates, 10 samples each at `scatter`, N = 256 planted with `factor`
/// below jamming; the scaling fit's phi_J and its window phi_J +- 0.01.
StatsData campaign(double factor, int rates, double scatter, std::mt19937_64& rng) {
  StatsData d;
  d.fit_phi_j = kPhiJ;
  d.fit_window_min = kPhiJ - 0.01;
  d.fit_window_max = kPhiJ + 0.01;
  for (int r = 0; r < rates; ++r) {
    const double rate = -5.0 - 0.5 * r;
    d.ensembles.push_back(
        ensemble(256, 0.4, rate, below_only(runs(10, 0.0, rng, 60, scatter), factor)));
    d.ensembles.push_back(ensemble(1024, 0.4, rate, runs(10, 0.0, rng, 60, scatter)));
  }
  return d;
}

const Verdict* find(const std::vector<Verdict>& v, double log10_rate, const std::string& region) {
  for (const auto& x : v)
    if (x.region == region && x.values.count("log10_rate") &&
        std::abs(x.values.at("log10_rate") - log10_rate) < 1e-9 && x.values.at("constant_z") == 0.0)
      return &x;
  return nullptr;
}

double binomial_slack(double rate, int n) {
  return 1.645 * std::sqrt(rate * (1 - rate) / n);
}

}  // namespace

BOOST_AUTO_TEST_CASE(regions_lie_around_phi_j_from_the_fit_else_the_jamming_points) {
  StatsData d;
  BOOST_TEST(!jamming_reference(d, std::nullopt).known());
  BOOST_TEST(regions_around(jamming_reference(d, std::nullopt), {}).empty());
  d.ensembles.push_back(ensemble(256, 0.4, -5, {{1, 2}, {1, 2}}));
  d.ensembles.push_back(ensemble(1024, 0.4, -5, {{1, 2}, {1, 2}}));
  d.ensembles[0].jamming_points = {0.80, 0.82};
  d.ensembles[1].jamming_points = {0.838, NAN, 0.842};  // the largest size's, NaN left out
  JammingReference j = jamming_reference(d, std::nullopt);
  BOOST_TEST(j.phi_j == 0.840, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(j.from.find("N = 1024") != std::string::npos, j.from);
  d.fit_phi_j = 0.8415;
  j = jamming_reference(d, std::nullopt);
  BOOST_TEST(j.phi_j == 0.8415);
  BOOST_TEST(jamming_reference(d, 0.85).phi_j == 0.85);
  const auto r = regions_around(j, {0.004, 0.012});
  BOOST_TEST_REQUIRE(r.size() == 3u);
  BOOST_TEST(r[0].name == "below");
  BOOST_TEST(r[0].min == 0.8295, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(r[0].max == r[1].min);
  BOOST_TEST(r[1].max == r[2].min);
  BOOST_TEST(r[2].max == 0.8535, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(an_effect_below_jamming_fails_the_region_below_and_no_other) {
  // 20% higher pressure below phi_J - 0.004 only (Delta p/p 0.18), 4% scatter per run, 10
  // samples per set: sigma_D in the region about 0.018, so the effect lies about 0.08 beyond
  // the 10% margin, 4.4 sigma_D, against a one-sided threshold of 3.1 (alpha 0.05 over 4 rates
  // x 2 grids x 4 verdicts): power per rate about 0.9. Required: the region below fails at 3
  // or more of the 4 rates; the regions at and above never fail.
  std::mt19937_64 rng(31);
  const StatsData d = campaign(1.2, 4, 0.04, rng);
  CheckOptions o;
  o.permutations = 400;
  const auto verdicts = finite_size_check(d, o);
  int below_fails = 0;
  for (int r = 0; r < 4; ++r) {
    const double rate = -5.0 - 0.5 * r;
    for (const char* region : {"pooled", "below", "at", "above"}) {
      const Verdict* v = find(verdicts, rate, region);
      BOOST_TEST_REQUIRE(v, "rate " << rate << " region " << region);
      BOOST_TEST_MESSAGE(rate << " " << region << ": " << v->status << ", estimate "
                              << v->estimate);
      if (std::string(region) == "below") below_fails += v->status == "fail";
      if (std::string(region) == "at" || std::string(region) == "above")
        BOOST_TEST(v->status != "fail", v->case_name << ": " << v->reason);
    }
    // The region below judges its own range, and says so.
    const Verdict* below = find(verdicts, rate, "below");
    BOOST_TEST(below->values.at("range_max") <= kPhiJ - 0.004 + 1e-9);
    BOOST_TEST(below->reason.find("below jamming, phi in [0.8280, 0.8360]") != std::string::npos,
               below->reason);
  }
  BOOST_TEST(below_fails >= 3);
  // checks.json carries the region of every verdict.
  BOOST_TEST(to_json(verdicts).find("\"region\": \"below\"") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_pooled_estimate_dilutes_what_the_region_below_measures) {
  // The same plant seen by the pooled verdict over the fit's window (phi_J +- 0.01): its
  // weighted mean spreads the 18% below jamming over points that have none, and reads a
  // third of it or less; only the pointwise rule (where the noise is small enough) or the
  // region below says how large the effect is where it is.
  std::mt19937_64 rng(31);
  const StatsData d = campaign(1.2, 4, 0.04, rng);
  CheckOptions o;
  o.permutations = 400;
  const auto verdicts = finite_size_check(d, o);
  for (int r = 0; r < 4; ++r) {
    const Verdict* pooled = find(verdicts, -5.0 - 0.5 * r, "pooled");
    const Verdict* below = find(verdicts, -5.0 - 0.5 * r, "below");
    BOOST_TEST_REQUIRE((pooled && below));
    // The pooled weighted mean (where the pointwise rule fails a verdict, its estimate is the
    // point's; the weighted mean stays in values.difference).
    const double pooled_mean = pooled->values.at("difference");
    BOOST_TEST(std::abs(pooled_mean) < below->estimate / 2,
               pooled_mean << " vs " << below->estimate);
    BOOST_TEST(below->estimate > 0.1);
  }
}

BOOST_AUTO_TEST_CASE(no_effect_no_more_alarms_than_alpha_over_regions_and_rates) {
  // Nothing planted, 300 campaigns of 2 rates: a "fail" in any region or rate, and a
  // difference detected in any of them (the false alarm the Bonferroni share controls),
  // each at most alpha plus the binomial allowance. alpha 0.5 keeps the permutations few
  // enough to repeat 300 times (each comparison then detects at 0.5 / 16).
  CheckOptions o;
  o.alpha = 0.5;
  o.permutations = 100;
  int fails = 0, alarms = 0;
  const int repeats = 300;
  for (int r = 0; r < repeats; ++r) {
    std::mt19937_64 rng(5000 + r);
    const StatsData d = campaign(1.0, 2, 0.1, rng);
    bool failed = false, alarmed = false;
    for (const auto& v : finite_size_check(d, o)) {
      failed = failed || v.status == "fail";
      alarmed = alarmed || (std::isfinite(v.threshold) && v.statistic > v.threshold);
    }
    fails += failed;
    alarms += alarmed;
  }
  BOOST_TEST_MESSAGE("nothing planted, 300 campaigns: a fail in " << fails << ", an alarm in "
                                                                  << alarms << " (alpha 0.5)");
  BOOST_TEST(fails / double(repeats) <= 0.05 + binomial_slack(0.05, repeats));
  BOOST_TEST(alarms / double(repeats) <= 0.5 + binomial_slack(0.5, repeats));
  BOOST_TEST(alarms > 0);  // the detection is not dead
}
