// The regression check against a stored baseline, on synthetic run sets (synthetic_runs.hpp):
// rerun samples must be bitwise identical (a one-ulp change fails, a tolerance admits it), new
// samples of the same distribution pass and a planted 15% shift fails, the whole check's
// false-alarm rate over several ensembles is measured, and what cannot be compared is inconclusive.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/regression_check.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

// A baseline of 10 samples (ids 0..9) per ensemble, and a rerun with samples 0 and 1 copied
// exactly plus `fresh` new samples (ids 10, 11, ...) shifted by `shift`.
struct Case {
  StatsData baseline, now;
};

Case make_case(std::mt19937_64& rng, double shift, int fresh = 8, int ensembles = 1) {
  Case c;
  for (int k = 0; k < ensembles; ++k) {
    const double rate = -3.0 - 0.5 * k;
    const auto base = runs(10, 0.0, rng);
    c.baseline.ensembles.push_back(ensemble(1024, 0.7, rate, base));
    auto rerun = ensemble(1024, 0.7, rate, {base[0], base[1]});
    const auto extra = ensemble(1024, 0.7, rate, runs(fresh, shift, rng), 10);
    for (std::size_t s = 0; s < extra.pressure_at_phi.size(); ++s) {
      rerun.pressure_at_phi.push_back(extra.pressure_at_phi[s]);
      rerun.sample_ids.push_back(extra.sample_ids[s]);
    }
    c.now.ensembles.push_back(std::move(rerun));
  }
  return c;
}

const Verdict& find(const std::vector<Verdict>& v, const std::string& what) {
  for (const auto& x : v)
    if (x.case_name.find(what) != std::string::npos) return x;
  throw std::runtime_error("no verdict " + what);
}

}  // namespace

BOOST_AUTO_TEST_CASE(identical_reruns_and_same_distribution_pass) {
  std::mt19937_64 rng(1);
  const Case c = make_case(rng, 0.0);
  // 8 new against 10 baseline samples with 10% scatter exclude effects down to about 20%.
  CheckOptions o;
  o.margins["regression"] = 0.3;
  const auto v = regression_check(c.now, c.baseline, o, {});
  BOOST_TEST(v.size() == 2u);
  BOOST_TEST(find(v, "identical").status == "pass");
  BOOST_TEST(find(v, "identical").statistic == 0.0);
  BOOST_TEST(find(v, "new samples").status == "pass", find(v, "new samples").reason);
  // At the default margin (10%) the same data cannot decide: inconclusive, never a pass.
  BOOST_TEST(find(regression_check(c.now, c.baseline, {}, {}), "new samples").status ==
             "inconclusive");
}

BOOST_AUTO_TEST_CASE(a_one_ulp_change_of_a_rerun_fails_unless_tolerated) {
  std::mt19937_64 rng(2);
  Case c = make_case(rng, 0.0);
  double& x = c.now.ensembles[0].pressure_at_phi[1][30];
  x = std::nextafter(x, 2 * x);
  const auto strict = regression_check(c.now, c.baseline, {}, {});
  BOOST_TEST(find(strict, "identical").status == "fail");
  BOOST_TEST(find(strict, "identical").statistic > 0.0);
  BOOST_TEST(find(strict, "identical").statistic < 1e-15);
  RegressionOptions loose;
  loose.tolerance = 1e-12;
  BOOST_TEST(find(regression_check(c.now, c.baseline, {}, loose), "identical").status == "pass");
  // A point that became NaN (a run that ended early) is a difference too.
  c.now.ensembles[0].pressure_at_phi[0][59] = NAN;
  BOOST_TEST(find(regression_check(c.now, c.baseline, {}, loose), "identical").status == "fail");
}

BOOST_AUTO_TEST_CASE(a_planted_shift_of_new_samples_fails) {
  // 15% with 10% sample scatter, 8 new samples against 10: detected (the finite-size test's
  // power at this size, measured in test_checks).
  std::mt19937_64 rng(3);
  const Case c = make_case(rng, 0.15);
  const auto v = regression_check(c.now, c.baseline, {}, {});
  BOOST_TEST(find(v, "identical").status == "pass");
  BOOST_TEST(find(v, "new samples").status == "fail");
  BOOST_TEST(find(v, "new samples").statistic > find(v, "new samples").threshold);
}

BOOST_AUTO_TEST_CASE(false_alarm_rate_of_the_whole_check_is_at_most_alpha) {
  // Three ensembles, no difference, 150 repeats: Bonferroni keeps the rate of any failure at
  // or below alpha = 0.05 (binomial sd 0.018 at 0.05; accept up to 0.10, and above 0 would
  // be expected but is not required of a conservative correction).
  std::mt19937_64 rng(4);
  CheckOptions o;
  o.permutations = 400;
  int alarms = 0;
  const int repeats = 150;
  for (int r = 0; r < repeats; ++r) {
    const Case c = make_case(rng, 0.0, 8, 3);
    bool any = false;
    for (const auto& v : regression_check(c.now, c.baseline, o, {}))
      any = any || v.status == "fail";
    alarms += any;
  }
  const double rate = static_cast<double>(alarms) / repeats;
  BOOST_TEST_MESSAGE("measured false-alarm rate of the regression check (3 ensembles): " << rate);
  BOOST_TEST(rate <= 0.10);
}

BOOST_AUTO_TEST_CASE(what_cannot_be_compared_is_inconclusive) {
  std::mt19937_64 rng(5);
  Case c = make_case(rng, 0.0, 1);                                          // one new sample only
  c.now.ensembles.push_back(ensemble(2048, 0.7, -3.0, runs(3, 0.0, rng)));  // not in baseline
  const auto v = regression_check(c.now, c.baseline, {}, {});
  BOOST_TEST(find(v, "identical").status == "pass");
  BOOST_TEST(find(v, "new samples").status == "inconclusive");
  BOOST_TEST(find(v, "n2048").status == "inconclusive");
  c.now.dim = 3;
  const auto other = regression_check(c.now, c.baseline, {}, {});
  BOOST_TEST(other.size() == 1u);
  BOOST_TEST(other[0].status == "inconclusive");
}
