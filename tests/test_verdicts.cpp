// Three outcomes against a margin (checks/margin.hpp), on synthetic run sets with a known
// truth: a planted effect fails; no effect with small noise passes; no effect with large noise
// is inconclusive (with an estimate of the samples that would decide it, which does decide it);
// a detected effect smaller than the margin passes, saying so. The false-alarm rate (a fail
// with nothing planted) and the false-pass rate (a pass with an effect beyond the margin
// planted) are measured over 300 repeats each and must be at or below alpha. A difference
// planted at t = 0 alone (the relaxed start's residual pressure) changes no verdict. Exit
// statuses of `jam check`: docs/statistics-and-checks.md.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/relative_difference.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

constexpr double kAlpha = 0.05;

/// One comparison of two synthetic sets judged at margin M: its verdict.
Verdict judged(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
               double margin, std::uint64_t seed = 1, int permutations = 400) {
  Verdict v;
  const RelativeDifference t =
      compare_run_sets(a, b, Levels::two_sided(kAlpha), permutations, seed);
  judge(v, t, Levels::two_sided(kAlpha), margin, std::min(a.size(), b.size()));
  return v;
}

/// The one-sided 95% upper limit of a rate measured as k of n: a measured rate above alpha by
/// more than this is evidence that the true rate exceeds alpha.
double binomial_slack(double alpha, int n) {
  return 1.645 * std::sqrt(alpha * (1 - alpha) / n);
}

}  // namespace

BOOST_AUTO_TEST_CASE(each_outcome_on_known_truth) {
  std::mt19937_64 rng(11);
  // A planted 30% effect, 10% scatter, 10 samples: detected, not within 10%.
  Verdict v = judged(runs(10, 0.3, rng), runs(10, 0.0, rng), 0.1);
  BOOST_TEST(v.status == "fail", v.reason);
  // No effect, 1% scatter: every effect above about 2% excluded, so within a 10% margin.
  v = judged(runs(10, 0.0, rng, 60, 0.01), runs(10, 0.0, rng, 60, 0.01), 0.1);
  BOOST_TEST(v.status == "pass", v.reason);
  BOOST_TEST(v.excluded_above <= 0.1);
  BOOST_TEST(v.margin == 0.1);
  // No effect, 30% scatter: nothing detected and nothing useful excluded.
  v = judged(runs(10, 0.0, rng, 60, 0.3), runs(10, 0.0, rng, 60, 0.3), 0.1);
  BOOST_TEST(v.status == "inconclusive", v.reason);
  BOOST_TEST(v.samples_needed > 10.0);
  BOOST_TEST(v.reason.find("(estimate)") != std::string::npos, v.reason);
  // A 3% effect with 0.5% scatter and 20 samples: detected, yet within the 10% margin.
  v = judged(runs(20, 0.03, rng, 60, 0.005), runs(20, 0.0, rng, 60, 0.005), 0.1);
  BOOST_TEST(v.status == "pass", v.reason);
  BOOST_TEST(v.reason.find("a smaller difference is detected") != std::string::npos, v.reason);
}

// The estimate of an inconclusive verdict: with that many samples per set, the same truth (no
// effect, 10% scatter, margin 15%) is decided in most repeats.
BOOST_AUTO_TEST_CASE(samples_needed_decides) {
  std::mt19937_64 rng(12);
  const Verdict first = judged(runs(6, 0.0, rng), runs(6, 0.0, rng), 0.15);
  BOOST_REQUIRE(first.status == "inconclusive");
  const int needed = static_cast<int>(first.samples_needed);
  BOOST_TEST_MESSAGE("6 samples per set inconclusive at margin 0.15; estimate " << needed);
  BOOST_REQUIRE(needed > 6);
  BOOST_REQUIRE(needed < 200);
  int decided = 0;
  for (int r = 0; r < 20; ++r) {
    decided +=
        judged(runs(needed, 0.0, rng), runs(needed, 0.0, rng), 0.15, r).status != "inconclusive";
  }
  BOOST_TEST_MESSAGE("decided with " << needed << " samples per set: " << decided << " of 20");
  BOOST_TEST(decided >= 10);
}

// Nothing planted, 300 repeats: a fail needs a detection at alpha, so it happens at most as
// often as a false alarm of the test (alpha). Measured here: see the message (and
// docs/statistics-and-checks.md).
BOOST_AUTO_TEST_CASE(false_alarm_rate_at_most_alpha) {
  std::mt19937_64 rng(13);
  const int repeats = 300;
  int fails = 0, passes = 0;
  for (int r = 0; r < repeats; ++r) {
    const Verdict v = judged(runs(10, 0.0, rng), runs(10, 0.0, rng), 0.1, 100 + r);
    fails += v.status == "fail";
    passes += v.status == "pass";
  }
  const double rate = static_cast<double>(fails) / repeats;
  BOOST_TEST_MESSAGE("false-alarm rate (fail, nothing planted, margin 0.1): " << rate << "; pass "
                                                                              << passes / 300.0);
  BOOST_TEST(rate <= kAlpha + binomial_slack(kAlpha, repeats));
}

// An effect just beyond the margin planted (true Delta p/p = 1.05 M), in 300 repeats at a
// scatter where the bound sits near the margin: a pass needs the simultaneous band to miss the
// truth, which happens at most at rate alpha.
BOOST_AUTO_TEST_CASE(false_pass_rate_at_most_alpha) {
  std::mt19937_64 rng(14);
  const double margin = 0.1;
  // Delta = 2 (p_A - p_B) / (p_A + p_B) = 2 s / (2 + s) for a shift s: s for Delta = 1.05 M.
  const double delta = 1.05 * margin, shift = 2 * delta / (2 - delta);
  const int repeats = 300;
  int passes = 0, fails = 0;
  for (int r = 0; r < repeats; ++r) {
    const Verdict v =
        judged(runs(20, shift, rng, 60, 0.01), runs(20, 0.0, rng, 60, 0.01), margin, 500 + r);
    passes += v.status == "pass";
    fails += v.status == "fail";
  }
  const double rate = static_cast<double>(passes) / repeats;
  BOOST_TEST_MESSAGE("false-pass rate (Delta = 1.05 M planted, 1% scatter): " << rate << "; fail "
                                                                              << fails / 300.0);
  BOOST_TEST(rate <= kAlpha + binomial_slack(kAlpha, repeats));
  BOOST_TEST(fails > repeats / 2);  // the test has power here: it is not passing by luck
}

// A difference at t = 0 alone (the relaxed start's residual pressure, index 0) changes no
// verdict of the finite-size, sample-pair or phi_init checks, however large.
BOOST_AUTO_TEST_CASE(a_difference_planted_at_the_start_changes_nothing) {
  std::mt19937_64 rng(15);
  auto with_start = [&](std::int64_t n, double phi_init, double start_pressure) {
    auto p = runs(10, 0.0, rng);
    for (auto& row : p) row[0] = start_pressure * (1.0 + 0.01 * row[1]);  // the start
    EnsembleTables e = ensemble(n, phi_init, -4.0, p);
    find_compressed_range(e, {});
    return e;
  };
  StatsData clean, planted;
  for (auto* d : {&clean, &planted}) {
    std::mt19937_64 same(16);
    rng = same;
    d->ensembles.push_back(with_start(1024, 0.80, 1e-8));
    d->ensembles.push_back(with_start(2048, 0.80, d == &planted ? 5e-8 : 1e-8));
    d->ensembles.push_back(with_start(1024, 0.78, 1e-8));
  }
  BOOST_TEST(clean.ensembles[0].compressed_from_phi == clean.ensembles[0].phi_grid[1]);
  CheckOptions o;
  o.permutations = 400;
  for (const char* check : {"finite_size", "sample_pairs", "phi_init"}) o.margins[check] = 0.3;
  const auto a = run_check("all", clean, o), b = run_check("all", planted, o);
  BOOST_REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    BOOST_TEST(a[k].status == b[k].status, a[k].case_name);
    BOOST_TEST((a[k].excluded_above == b[k].excluded_above || std::isnan(a[k].excluded_above)),
               a[k].case_name);
  }
  // Without the rule the start decides: the same plant fails the size comparison.
  const RelativeDifference whole =
      compare_run_sets(clean.ensembles[0].pressure_at_phi, planted.ensembles[1].pressure_at_phi,
                       Levels::two_sided(kAlpha));
  BOOST_TEST(whole.p_value <= kAlpha);
}
