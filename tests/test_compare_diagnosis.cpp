// Why two codes differ, as the compare check says it (checks/compare_diagnosis.hpp), on small
// campaigns of open runs imported and averaged as a user's would be (import, stats.h5,
// compare): 64 particles from phi 0.80 at rate 1e-4, 8 runs a side unless said, each a
// pressure that builds up over the start's transient and then grows as exp(30 phi), with 1%
// correlated scatter per run; output every 0.001 in phi on the campaign's grid of 0.0005.
//   - DIR imported as inertial at Q = 2 (or with the Hertzian contact) against REF overdamped:
//     every verdict names the difference; the same model names nothing;
//   - DIR's pressure planted 40% above REF's at the start, decaying over 0.004 in packing (a
//     start relaxed otherwise, as a CG-minimised one): the failure says it lies only just after
//     the start and points at the start protocol; a difference everywhere says nothing of it;
//   - one run a side: "needs at least 2 samples per set (DIR has 1)", for the pressure and the
//     jamming points; two runs are judged;
//   - no claim about the start where nothing past it could be judged, or only a sliver;
//   - too few runs to decide: the samples that would decide it, split per side.
#include <fmt/format.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "campaign/external_campaign.hpp"
#include "checks/checks.hpp"
#include "checks/compare_diagnosis.hpp"
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

/// Its campaigns: 1% scatter, a planted shift everywhere, each run with a jamming point.
struct Design : jam::test::CompareDesign {
  Design() {
    scatter = 0.01;
    jamming_point = true;
  }
};

const jam::test::ScratchDir kDir("compare-diagnosis");

fs::path scratch() { return kDir.path(); }

StatsData campaign(const fs::path& root, const std::string& name, const Design& d,
                   std::uint64_t seed) {
  return jam::test::compare_campaign(root, name, d, seed);
}

std::vector<Verdict> compare(const StatsData& dir, const StatsData& ref) {
  CheckOptions o;
  o.permutations = 400;
  return compare_check(dir, ref, o, {});
}

/// The pooled verdicts of one check (the regions placed by <Z> are judged beside them).
std::vector<Verdict> pooled(const std::vector<Verdict>& all, const std::string& check) {
  std::vector<Verdict> out;
  for (const auto& v : all)
    if (v.check == check && (v.region.empty() || v.region == "pooled")) out.push_back(v);
  return out;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_model_difference_is_named_in_every_verdict) {
  const fs::path root = scratch();
  const StatsData ref = campaign(root, "ref", {}, 1);
  Design inertial;
  inertial.dynamics = "inertial";
  inertial.quality_factor = 2;
  const auto named = compare(campaign(root, "inertial", inertial, 2), ref);
  BOOST_TEST_REQUIRE(!named.empty());
  for (const auto& v : named) {
    BOOST_TEST(has(v.reason,
                   "the two sides' models differ (DIR against REF, as their campaign "
                   "directories record them): dynamics inertial (Q 2) against "
                   "overdamped"),
               v.check << " " << v.case_name << ": " << v.reason);
    BOOST_TEST(v.values.count("model_differs") == 1u);
  }
  Design hertzian;
  hertzian.contact = "hertzian";
  for (const auto& v : compare(campaign(root, "hertzian", hertzian, 3), ref))
    BOOST_TEST(has(v.reason,
                   "differ (DIR against REF, as their campaign directories record "
                   "them): contact hertzian against harmonic"),
               v.reason);
  // The same model: nothing named.
  for (const auto& v : compare(campaign(root, "same", {}, 4), ref)) {
    BOOST_TEST(!has(v.reason, "models differ"), v.reason);
    BOOST_TEST(v.values.count("model_differs") == 0u);
  }
  // A planned campaign's model is its campaign.toml's; a directory with neither file has none.
  const fs::path planned = root / "planned";
  fs::create_directories(planned);
  std::ofstream(planned / "campaign.toml")
      << "name = \"p\"\ndim = 2\nsizes = [64]\nphi_init = [0.8]\nlog10_rates = [-4]\n"
         "samples = 2\nseed = 1\nphi_stop = 0.84\noutput = \"p\"\ndynamics = \"inertial\"\nq = "
         "0.5\n";
  const auto model = campaign_model(planned.string());
  BOOST_TEST_REQUIRE(model.has_value());
  BOOST_TEST(model->dynamics == "inertial");
  BOOST_TEST(model_difference(*model, *campaign_model((root / "ref").string())) ==
             "dynamics inertial (Q 0.5) against overdamped");
  BOOST_TEST(!campaign_model((root / "inertial-sources").string()).has_value());
  fs::remove_all(root);
}

BOOST_AUTO_TEST_CASE(a_failure_only_just_after_the_start_points_at_the_start_protocol) {
  const fs::path root = scratch();
  const StatsData ref = campaign(root, "ref", {}, 5);
  Design start;
  start.start_shift = 0.4;  // 10% at phi 0.8055, 2.9% at 0.8105, 0.8% at 0.8155
  const auto at_start = pooled(compare(campaign(root, "start", start, 6), ref), "compare");
  BOOST_TEST_REQUIRE(at_start.size() == 2u);  // constant phi and constant Z
  int fails = 0;
  for (const auto& v : at_start) {
    if (v.status != "fail") continue;
    ++fails;
    BOOST_TEST(has(v.reason,
                   "fails only just after the start, a sign of another start protocol: "
                   "judged from "),
               v.reason);
    BOOST_TEST(has(v.reason,
                   "relax each start with damped dynamics as jam does "
                   "(docs/porting.md, \"Relax the start with damped dynamics, not CG "
                   "minimisation\")"),
               v.reason);
    BOOST_TEST(short_reason(v) ==
               "fails only just after the start, a sign of another start "
               "protocol");
    BOOST_TEST(v.values.at("start_only") == 1.0);
    if (v.values.at("constant_z") == 0.0)
      BOOST_TEST(v.values.at("past_start") == v.values.at("compared_from") + kStartSection,
                 boost::test_tools::tolerance(1e-9));
  }
  BOOST_TEST(fails >= 1);
  // 15% everywhere fails past the start too: nothing said of the start.
  Design everywhere;
  everywhere.shift = 0.15;
  fails = 0;
  for (const auto& v :
       pooled(compare(campaign(root, "everywhere", everywhere, 7), ref), "compare")) {
    fails += v.status == "fail";
    BOOST_TEST(!has(v.reason, "just after the start"), v.reason);
    BOOST_TEST(v.values.count("start_only") == 0u);
  }
  BOOST_TEST(fails == 2);
  fs::remove_all(root);
}

BOOST_AUTO_TEST_CASE(one_sample_a_side_names_the_count) {
  const fs::path root = scratch();
  const StatsData ref = campaign(root, "ref", {}, 8);
  Design one;
  one.samples = 1;
  const StatsData single = campaign(root, "one", one, 9);
  const auto all = compare(single, ref);
  const auto pressure = pooled(all, "compare");
  BOOST_TEST_REQUIRE(pressure.size() == 2u);
  for (const auto& v : pressure) {
    BOOST_TEST(v.status == "inconclusive");
    BOOST_TEST(v.reason == "needs at least 2 samples per set (DIR has 1)", v.reason);
    BOOST_TEST(v.values.at("samples_a") == 1.0);
    BOOST_TEST(v.values.at("samples_b") == 8.0);
  }
  const auto jamming = pooled(all, "compare_jamming");
  BOOST_TEST_REQUIRE(jamming.size() == 1u);
  BOOST_TEST(jamming[0].status == "inconclusive");
  BOOST_TEST(
      has(jamming[0].reason, "needs at least 2 samples per set (DIR has 1 with a jamming point)"),
      jamming[0].reason);
  // Two runs are enough to be judged.
  Design two;
  two.samples = 2;
  for (const auto& v : pooled(compare(campaign(root, "two", two, 13), ref), "compare")) {
    BOOST_TEST(!has(v.reason, "needs at least 2 samples"), v.reason);
    BOOST_TEST(v.values.at("samples_a") == 2.0);
  }
  // Both sides alone: both named.
  for (const auto& v : pooled(compare(single, campaign(root, "one-ref", one, 10)), "compare"))
    BOOST_TEST(v.reason == "needs at least 2 samples per set (DIR has 1, REF has 1)", v.reason);
  fs::remove_all(root);
}

BOOST_AUTO_TEST_CASE(an_undecided_comparison_names_the_cheapest_split_per_side) {
  // 3 runs against 8 at 15% scatter: more runs would decide it, the cheaper side's more so.
  const fs::path root = scratch();
  Design few, many;
  few.samples = 3;
  few.scatter = many.scatter = 0.15;
  int undecided = 0;
  for (const auto& v : pooled(
           compare(campaign(root, "few", few, 11), campaign(root, "many", many, 12)), "compare")) {
    if (v.status != "inconclusive" || !std::isfinite(v.samples_needed)) continue;
    ++undecided;
    const double a = v.values.at("samples_needed_a"), b = v.values.at("samples_needed_b");
    BOOST_TEST(has(v.reason, fmt::format("cheapest split {:.0f} of DIR and {:.0f} of REF", a, b)),
               v.reason);
    BOOST_TEST(has(short_reason(v), fmt::format("cheapest: {:.0f} of the first set, {:.0f} of "
                                                "the second",
                                                a, b)),
               short_reason(v));
    BOOST_TEST(table_row(v).samples == "3, 8");
  }
  BOOST_TEST(undecided >= 1);
  fs::remove_all(root);
}

// Judged again on nothing (no data past the start), or with the start only a sliver short of
// the range's end: no claim about the start.
BOOST_AUTO_TEST_CASE(no_start_claim_without_a_judgement_past_it) {
  Verdict v;
  v.check = "compare";
  v.status = "fail";
  v.reason = "the effect surely exceeds the margin";
  v.values = {{"range_min", 0.80}, {"range_max", 0.86}};
  PoolRange asked;
  asked.min = 0.80;
  asked.max = 0.86;
  const RangeData nothing = [](const PoolRange&, Verdict&) { return Aligned{}; };
  Verdict judged = v;
  say_if_only_at_start(judged, asked, 0.81, nothing, {}, 0.05, 100);
  BOOST_TEST(judged.reason == v.reason);
  BOOST_TEST(judged.values.count("start_only") == 0u);
  // The range past the start less than half the range judged: not judged again at all.
  const RangeData never = [](const PoolRange&, Verdict&) -> Aligned {
    throw std::logic_error("judged again");
  };
  Verdict sliver = v;
  BOOST_CHECK_NO_THROW(say_if_only_at_start(sliver, asked, 0.835, never, {}, 0.05, 100));
  BOOST_TEST(sliver.reason == v.reason);
}
