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
#include "open_run_fixture.hpp"
#include "sim/io/open_run.hpp"
#include "stats/campaign_stats.hpp"

namespace fs = std::filesystem;
using namespace jam::checks;

namespace {

struct Design {
  double shift = 0.0;       // the pressure multiplied by 1 + shift for phi > 0.82
  double stop = 0.86;       // the last output packing of every run ...
  double stop_first = NAN;  // ... but of sample 0, when given
  int every = 1;            // every how many of the 0.001-spaced points is written
  double scatter = 0.05;    // of one run's pressure
};

/// One run: p = 1e-3 exp(30 (phi - 0.84)) (1 + 1e-3 - exp(-(phi - 0.8) / 0.0015)) exp(eps),
/// eps an Ornstein-Uhlenbeck process (5% unless given, correlation length 0.005); Z rising
/// from 3.5.
jam::OpenRun synthetic_run(int sample, const Design& d, std::mt19937_64& rng) {
  jam::OpenRun r = jam::test::open_run_of(64, 1e-4, 0.80, sample);
  std::normal_distribution<double> g(0.0, 1.0);
  const double rho = std::exp(-0.001 / 0.005), scatter = d.scatter;
  double eps = scatter * g(rng);
  const double stop = sample == 0 && std::isfinite(d.stop_first) ? d.stop_first : d.stop;
  for (int k = 0; 0.80 + 0.001 * k <= stop + 1e-9; ++k) {
    const double phi = 0.80 + 0.001 * k;
    if (k > 0) eps = rho * eps + scatter * std::sqrt(1 - rho * rho) * g(rng);
    if (k % d.every != 0) continue;
    const double build_up = 1 + 1e-3 - std::exp(-(phi - 0.80) / 0.0015);
    r.packing_fraction.push_back(phi);
    r.pressure.push_back(1e-3 * std::exp(30 * (phi - 0.84)) * build_up *
                         (phi > 0.82 ? 1 + d.shift : 1.0) * std::exp(eps));
    r.contacts_per_particle.push_back(3.5 + 15 * (phi - 0.80));
  }
  return r;
}

/// A campaign of 8 such runs imported into root/name, averaged; its stats.h5 as compare reads it.
StatsData campaign(const fs::path& root, const std::string& name, const Design& d,
                   std::uint64_t seed) {
  const fs::path sources = root / (name + "-sources"), dir = root / name;
  fs::remove_all(sources);
  fs::remove_all(dir);
  fs::create_directories(sources);
  std::mt19937_64 rng(seed);
  std::vector<std::string> files;
  for (int s = 0; s < 8; ++s) {
    files.push_back((sources / ("run" + std::to_string(s) + ".h5")).string());
    jam::write_open_run(files.back(), synthetic_run(s, d, rng));
  }
  jam::import_runs(dir.string(), files, {});
  jam::stats::StatsOptions o;
  o.fit = false;  // one rate: no scaling fit, so REF's range is past the transients to its end
  jam::stats::write_stats_file((dir / "stats.h5").string(),
                               jam::stats::compute_campaign_stats(dir.string(), o), o);
  return read_stats(dir.string());
}

fs::path scratch() {
  const fs::path d =
      fs::temp_directory_path() / ("jam-compare-ranges-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
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
