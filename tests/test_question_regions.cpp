// Where a campaign without a scaling fit is judged (checks/regions.hpp): its regions lie around
// the packing where <Z> of the largest size at the slowest rate crosses isostaticity, 2D; when
// <Z> never crosses it the pooled verdict over the whole compression says so, in its reason,
// its values and the table's line for the check; and a range the campaign asks about
// ([question] phi_min, phi_max) is judged as the region "asked", where a size effect confined
// to it fails although the pooled verdict over the whole compression passes. The data:
// synthetic_runs.hpp's grid, 60 points at 0.001 from phi 0.80, no fit, no jamming points.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "checks/checks.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/verdict.hpp"
#include "checks/verdict_file.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

/// <Z> rising through 4 at phi = at, linearly (25 per unit packing) along the grid.
std::vector<double> z_through(double at, std::size_t points = 60) {
  std::vector<double> z;
  for (std::size_t k = 0; k < points; ++k) z.push_back(4.0 + 25.0 * (0.80 + 0.001 * k - at));
  return z;
}

/// A run set on a fine grid (300 points at 0.0002 from phi 0.80) whose points scatter
/// independently, 20% each, with `effect` added to Delta p/p in [lo, hi] only.
EnsembleTables independent(std::int64_t n, int samples, double effect, double lo, double hi,
                           std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> t;
  for (int s = 0; s < samples; ++s) {
    std::vector<double> row;
    for (std::size_t k = 0; k < 300; ++k) {
      const double phi = 0.80 + 0.0002 * static_cast<double>(k);
      const double inside = phi >= lo - 1e-9 && phi <= hi + 1e-9 ? effect : 0.0;
      row.push_back(std::exp(30 * (phi - 0.84)) * (1 + inside) * std::exp(0.2 * g(rng)));
    }
    t.push_back(std::move(row));
  }
  EnsembleTables e = ensemble(n, 0.4, -5, t);
  for (std::size_t k = 0; k < e.phi_grid.size(); ++k) e.phi_grid[k] = 0.80 + 0.0002 * k;
  return e;
}

const Verdict* find(const std::vector<Verdict>& v, const std::string& region) {
  for (const auto& x : v)
    if (x.region == region && x.values.count("constant_z") && x.values.at("constant_z") == 0.0)
      return &x;
  return nullptr;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_regions_lie_where_z_of_the_largest_size_at_the_slowest_rate_crosses_2d) {
  std::mt19937_64 rng(3);
  StatsData d;  // 2D, no fit, no jamming points
  for (double rate : {-5.0, -5.5}) {
    for (std::int64_t n : {256, 1024}) {
      d.ensembles.push_back(ensemble(n, 0.4, rate, runs(6, 0.0, rng, 60, 0.04)));
      // Only N = 1024 at 1e-5.5 crosses at 0.842; the others elsewhere, to be passed over.
      d.ensembles.back().z_at_phi = z_through(n == 1024 && rate == -5.5 ? 0.842 : 0.83);
    }
  }
  const JammingReference j = jamming_reference(d, std::nullopt);
  BOOST_TEST(j.phi_j == 0.842, boost::test_tools::tolerance(1e-9));
  BOOST_TEST(has(j.from, "the packing 0.84200 where <Z> of N = 1024 at rate 1e-5.5 crosses 2D = 4"),
             j.from);
  // The fit and the jamming points, when there, come first.
  d.ensembles[3].jamming_points = {0.839, 0.841};
  BOOST_TEST(jamming_reference(d, std::nullopt).phi_j == 0.840, boost::test_tools::tolerance(1e-9));
  d.ensembles[3].jamming_points.clear();

  CheckOptions o;
  o.permutations = 200;
  const auto verdicts = finite_size_check(d, o);
  for (const char* region : {"pooled", "below", "at", "above"})
    BOOST_TEST_REQUIRE(find(verdicts, region), region);
  const Verdict* below = find(verdicts, "below");
  BOOST_TEST(has(below->reason,
                 "below jamming, phi in [0.8300, 0.8380], relative to the packing "
                 "0.84200 where <Z> of N = 1024 at rate 1e-5.5 crosses 2D = 4"),
             below->reason);
  BOOST_TEST(!find(verdicts, "pooled")->values.count("whole_compression"));
  BOOST_TEST(!has(format_table(verdicts), "WHOLE COMPRESSION"));
  // A chained slow rate that starts above 2D: the next ensemble in that order places them.
  d.ensembles[3].z_at_phi = z_through(0.79);
  BOOST_TEST(jamming_reference(d, std::nullopt).phi_j == 0.83, boost::test_tools::tolerance(1e-9));
}

BOOST_AUTO_TEST_CASE(z_below_2d_throughout_pools_the_whole_compression_and_says_so) {
  std::mt19937_64 rng(4);
  StatsData d;
  d.ensembles.push_back(ensemble(256, 0.4, -5, runs(6, 0.0, rng, 60, 0.04)));
  d.ensembles.push_back(ensemble(1024, 0.4, -5, runs(6, 0.0, rng, 60, 0.04)));
  for (auto& e : d.ensembles) e.z_at_phi = std::vector<double>(60, 3.5);
  const JammingReference j = jamming_reference(d, std::nullopt);
  BOOST_TEST(!j.known());
  BOOST_TEST(has(j.from,
                 "<Z> of N = 1024 at rate 1e-5 stays below 2D = 4 (at most 3.5) within "
                 "the data"),
             j.from);
  CheckOptions o;
  o.permutations = 200;
  const auto verdicts = finite_size_check(d, o);
  BOOST_TEST(verdicts.size() == 2u);  // constant phi and constant Z (no Z grid here), pooled
  for (const auto& v : verdicts) BOOST_TEST(v.region == "pooled");
  const Verdict* v = find(verdicts, "pooled");
  BOOST_TEST_REQUIRE(v);
  BOOST_TEST(v->values.count("whole_compression"), v->case_name);
  BOOST_TEST(has(v->reason, "pooled over the whole compression: no range asked"), v->reason);
  BOOST_TEST(has(v->reason, "stays below 2D = 4"), v->reason);
  // On the terminal: the line under the check's heading, not only the JSON.
  const std::string table = format_table(verdicts);
  BOOST_TEST(has(table, "finite_size: 2 verdicts"), table);
  BOOST_TEST(has(table, "POOLED OVER THE WHOLE COMPRESSION: no range asked"), table);
  BOOST_TEST(has(to_json(verdicts), "\"whole_compression\": 1.0"));
  // No <Z> stored at all: said the same way.
  for (auto& e : d.ensembles) e.z_at_phi.clear();
  BOOST_TEST(has(jamming_reference(d, std::nullopt).from, "no <Z> at constant phi in stats.h5"));
}

BOOST_AUTO_TEST_CASE(an_effect_only_in_the_range_asked_fails_it_while_the_whole_pool_passes) {
  // 24% higher pressure at N = 256 in [0.83, 0.844] only (71 of 300 points), 20% independent
  // scatter per point, 12 samples per set, no fit, no jamming points, no <Z>. The range asked
  // averages its 71 points and its interval lies wholly above the 10% margin in every one of
  // 10 campaigns; the pool over all 300 points dilutes the effect to about 6% and passes
  // (effects above 10% excluded) unless the pointwise rule finds one point surely beyond the
  // margin (measured: 4 of 20 seeds). Required: the range asked fails in 10 of 10 campaigns,
  // and in 6 or more of them the pooled verdict passes beside it, as it does without the
  // range asked (the same data, judged pooled only, say nothing else).
  int asked_fails = 0, pooled_passes = 0;
  for (int seed = 0; seed < 10; ++seed) {
    std::mt19937_64 rng(100 + seed);
    StatsData d;
    d.ensembles.push_back(independent(256, 12, 0.24, 0.83, 0.844, rng));
    d.ensembles.push_back(independent(1024, 12, 0.0, 0.83, 0.844, rng));
    CheckOptions o;
    o.permutations = 200;
    const auto unasked = finite_size_check(d, o);
    BOOST_TEST_REQUIRE(find(unasked, "pooled"));
    BOOST_TEST(!find(unasked, "asked"));
    o.regions.asked_min = 0.83;
    o.regions.asked_max = 0.844;
    const auto verdicts = finite_size_check(d, o);
    const Verdict* pooled = find(verdicts, "pooled");
    const Verdict* asked = find(verdicts, "asked");
    BOOST_TEST_REQUIRE((pooled && asked));
    BOOST_TEST_MESSAGE("seed " << seed << ": pooled " << pooled->status << " (alone "
                               << find(unasked, "pooled")->status << "), asked " << asked->status);
    asked_fails += asked->status == "fail";
    pooled_passes += pooled->status == "pass" && find(unasked, "pooled")->status == "pass";
    BOOST_TEST(asked->estimate > 0.1);
    BOOST_TEST(asked->case_name.ends_with(", range asked"), asked->case_name);
    BOOST_TEST(has(asked->reason,
                   "the range asked ([question] phi_min, phi_max), phi in "
                   "[0.8300, 0.8440]"),
               asked->reason);
    BOOST_TEST(asked->values.at("range_min") >= 0.83 - 1e-9);
    BOOST_TEST(asked->values.at("range_max") <= 0.844 + 1e-9);
    // Beside a range asked, the pool is not the only answer: no whole-compression words.
    BOOST_TEST(!pooled->values.count("whole_compression"));
    BOOST_TEST(find(unasked, "pooled")->values.count("whole_compression"));
    if (seed == 0) BOOST_TEST(has(to_json(verdicts), "\"region\": \"asked\""));
  }
  BOOST_TEST(asked_fails == 10);
  BOOST_TEST(pooled_passes >= 6);
  // One more verdict per comparison: the detection level is shared over pooled and asked.
  CheckOptions o;
  o.regions.asked_min = 0.83;
  o.regions.asked_max = 0.844;
  BOOST_TEST(verdicts_per_comparison(JammingReference{}, o.regions) == 2u);
}
