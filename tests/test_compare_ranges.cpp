// Where the compare check (checks/compare_check.cpp, compare_coverage.hpp) judges, on small
// campaigns of open runs imported and averaged as a user's would be (import, `jam stats`,
// stats.h5, compare): 64 particles from phi 0.80 at rate 1e-4, 8 runs a side, each a pressure
// that builds up over the start's transient and then grows as exp(30 phi), with 5% correlated
// scatter per run; output every 0.001 in phi on the campaign's grid of 0.0005.
//   - DIR's pressure planted 15% above REF's for phi > 0.82 fails, and still fails when
//     sample 0 of each side stops at phi 0.815 (as a run that crashed would): the short runs
//     are left out by name and the range stays REF's, never shrunk to [0.80, 0.815];
//   - equal physics judged on a sliver of REF's range (every DIR run stops at 0.815) is not a
//     pass: inconclusive, saying the range judged and the range asked;
//   - the same physics exported every 10th or 20th output point (0.01, 0.02 apart) does not
//     fail: such output is flagged and judged from one output step past the transient.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "campaign/external_campaign.hpp"
#include "checks/checks.hpp"
#include "checks/regression_check.hpp"
#include "checks/stats_data.hpp"
#include "compare_campaigns.hpp"
#include "open_run_fixture.hpp"
#include "scratch.hpp"
#include "sim/io/open_run.hpp"
#include "stats/campaign_stats.hpp"

namespace fs = std::filesystem;
using namespace jam::checks;

namespace {

/// Its campaigns: 5% scatter, a planted shift above phi 0.82.
struct Design : jam::test::CompareDesign {
  Design() { shift_above = 0.82; }
};

const jam::test::ScratchDir kDir("compare-ranges");

fs::path scratch() { return kDir.path(); }

StatsData campaign(const fs::path& root, const std::string& name, const Design& d,
                   std::uint64_t seed) {
  return jam::test::compare_campaign(root, name, d, seed);
}

/// The pooled compare verdicts (what these cases are about: the range judged); the regions
/// placed by <Z> are judged beside them and covered by test_question_regions.
std::vector<Verdict> pressure(const StatsData& dir, const StatsData& ref) {
  CheckOptions o;
  o.permutations = 400;
  std::vector<Verdict> out;
  for (auto& v : compare_check(dir, ref, o, {}))
    if (v.check == "compare" && (v.region.empty() || v.region == "pooled"))
      out.push_back(std::move(v));
  return out;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_short_run_does_not_steer_where_compare_judges) {
  const fs::path root = scratch();
  Design planted;
  planted.shift = 0.15;
  const Design equal;
  // Every run to 0.86: the planted difference fails.
  int fails = 0;
  for (const auto& v : pressure(campaign(root, "dir", planted, 1), campaign(root, "ref", equal, 2)))
    fails += v.status == "fail";
  BOOST_TEST(fails >= 1);
  // Sample 0 of each side stops at 0.815: it is left out by name, the others judged to 0.86.
  planted.stop_first = 0.815;
  Design ref_short = equal;
  ref_short.stop_first = 0.815;
  const auto verdicts =
      pressure(campaign(root, "dir-short", planted, 1), campaign(root, "ref-short", ref_short, 2));
  BOOST_TEST_REQUIRE(verdicts.size() == 2u);  // constant phi and constant Z, pooled
  fails = 0;
  for (const auto& v : verdicts) {
    fails += v.status == "fail";
    BOOST_TEST(v.status != "pass", v.case_name << ": " << v.reason);
    BOOST_TEST(has(v.reason, "left out: DIR sample 0 (data to "), v.reason);
    BOOST_TEST(has(v.reason, "REF sample 0 (data to "), v.reason);
    BOOST_TEST(v.values.at("left_out_dir") == 1.0);
    BOOST_TEST(has(v.reason, "DIR 7 samples, REF 7"), v.reason);
    if (v.values.at("constant_z") == 0.0) {
      BOOST_TEST(v.values.at("asked_max") > 0.859, v.reason);
      BOOST_TEST(v.values.at("range_max") > 0.85, v.reason);  // judged: never [0.80, 0.815]
      BOOST_TEST(has(v.reason, "up to REF's end"), v.reason);
    }
  }
  BOOST_TEST(fails >= 1);
  fs::remove_all(root);
}

BOOST_AUTO_TEST_CASE(a_pass_on_a_sliver_of_the_range_asked_is_inconclusive) {
  const fs::path root = scratch();
  // 1% scatter: on its part of the range the comparison passes (and did, as the whole answer).
  Design short_dir, whole;
  short_dir.stop = 0.815;  // every DIR run: a quarter of REF's range
  short_dir.scatter = whole.scatter = 0.01;
  const auto verdicts =
      pressure(campaign(root, "dir-sliver", short_dir, 3), campaign(root, "ref-whole", whole, 4));
  BOOST_TEST_REQUIRE(!verdicts.empty());
  for (const auto& v : verdicts) {
    if (v.values.at("constant_z") == 1.0) continue;
    BOOST_TEST(v.status == "inconclusive", v.case_name << ": " << v.reason);
    BOOST_TEST(v.values.at("range_max") < 0.816, v.reason);
    BOOST_TEST(v.values.at("asked_max") > 0.859, v.reason);
    BOOST_TEST(has(v.reason, "judged over phi [0.8"), v.reason);
    BOOST_TEST(has(v.reason, "less than 50% of the range asked [0.8"), v.reason);
    BOOST_TEST(has(v.reason, "within that part: within the margin"), v.reason);
  }
  fs::remove_all(root);
}

BOOST_AUTO_TEST_CASE(coarse_output_of_the_same_physics_does_not_fail) {
  const fs::path root = scratch();
  const StatsData ref = campaign(root, "ref-fine", {}, 5);
  for (int every : {10, 20}) {
    Design coarse;
    coarse.every = every;
    const std::string name = "dir-every-" + std::to_string(every);
    const auto verdicts = pressure(campaign(root, name, coarse, 6 + every), ref);
    BOOST_TEST_REQUIRE(!verdicts.empty());
    for (const auto& v : verdicts) {
      BOOST_TEST(v.status != "fail", every << " " << v.case_name << ": " << v.reason);
      BOOST_TEST(has(v.reason, "DIR's output is far coarser than the grid"), v.reason);
      BOOST_TEST(v.values.at("coarse_step") == 0.001 * every, boost::test_tools::tolerance(1e-9));
      // Judged from one output step past the transient (kStartTransient 0.005 past the start).
      if (v.values.at("constant_z") == 0.0)
        BOOST_TEST(v.values.at("range_min") >= 0.805 + 0.001 * every - 1e-9, v.reason);
    }
  }
  fs::remove_all(root);
}
