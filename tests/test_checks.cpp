// The statistical checks on synthetic run sets with run-to-run correlated noise: each passes
// on data that should pass and fails on data with a planted difference, the false-alarm rate
// of the finite-size test is measured over many repeats, and the JSON and JUnit outputs parse.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "checks/checks.hpp"
#include "checks/relative_difference.hpp"
#include "checks/verdict_file.hpp"
#include "sim/io/process.hpp"
#include "synthetic_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

BOOST_AUTO_TEST_CASE(finite_size_false_alarm_rate_is_nominal) {
  // Two independent run sets from the same distribution, 400 times: the fraction of failures
  // at alpha = 0.05 must be near 0.05 (binomial sd 0.011 for 400 repeats; accept 0.02 .. 0.09).
  std::mt19937_64 rng(1);
  int alarms = 0;
  const int repeats = 400;
  for (int r = 0; r < repeats; ++r) {
    const auto a = runs(10, 0.0, rng), b = runs(10, 0.0, rng);
    alarms += compare_run_sets(a, b, Levels::two_sided(0.05), 400, 1000 + r).p_value <= 0.05;
  }
  const double rate = double(alarms) / repeats;
  BOOST_TEST_MESSAGE("measured false-alarm rate at alpha 0.05: " << rate);
  BOOST_TEST(rate > 0.02);
  BOOST_TEST(rate < 0.09);
}

BOOST_AUTO_TEST_CASE(finite_size_detects_a_planted_difference_and_bounds_what_it_excludes) {
  std::mt19937_64 rng(2);
  // 15% systematic difference with 10% sample scatter and 10 samples each: detected.
  const auto a = runs(10, 0.15, rng), b = runs(10, 0.0, rng);
  const RelativeDifference r = compare_run_sets(a, b, Levels::two_sided(0.05));
  BOOST_TEST(r.p_value <= 0.05);
  BOOST_TEST(r.statistic > r.critical);
  // No difference: passes, and the excluded bound covers the (zero) truth with a margin
  // comparable to the detectable effect.
  const auto c = runs(10, 0.0, rng);
  const RelativeDifference s = compare_run_sets(c, b, Levels::two_sided(0.05));
  BOOST_TEST(s.p_value > 0.05);
  BOOST_TEST(s.excluded_above > 0.0);
  BOOST_TEST(s.excluded_above < 0.3);
  BOOST_TEST(s.detectable > 0.01);
  BOOST_TEST(s.detectable < s.excluded_above);
  BOOST_CHECK_THROW(compare_run_sets({a[0]}, b, Levels::two_sided(0.05)), std::invalid_argument);
}

BOOST_AUTO_TEST_CASE(checks_on_stats_data_pass_and_fail_as_planted) {
  std::mt19937_64 rng(3);
  StatsData clean, planted;
  for (double rate : {-3.0, -4.0}) {
    clean.ensembles.push_back(ensemble(1024, 0.6, rate, runs(10, 0.0, rng)));
    clean.ensembles.push_back(ensemble(2048, 0.6, rate, runs(10, 0.0, rng)));
    clean.ensembles.push_back(ensemble(1024, 0.8, rate, runs(10, 0.0, rng)));
    planted.ensembles.push_back(ensemble(1024, 0.6, rate, runs(10, 0.0, rng)));
    planted.ensembles.push_back(ensemble(2048, 0.6, rate, runs(10, rate == -3.0 ? 1.2 : 0.0, rng)));
    planted.ensembles.push_back(
        ensemble(1024, 0.8, rate, runs(10, rate == -3.0 ? -0.75 : 0.0, rng)));
  }
  CheckOptions o;
  o.permutations = 500;
  o.phi_min = 0.80;
  // 10 samples with 10% scatter, pooled over 60 points, exclude mean differences down to
  // about 10% and pair differences down to about 10-15%: margins of 0.4 and 0.2 these data
  // decide (test_verdicts.cpp covers the inconclusive outcome). The planted differences
  // (Delta p/p 0.75 and -1.2) lie so far beyond them that the data exclude every effect at or
  // below the margin (a fail needs that: margin.hpp), about 0.3 below |Delta| here.
  o.margins = {{"finite_size", 0.4}, {"phi_init", 0.4}, {"sample_pairs", 0.2}};
  int passed = 0;
  for (const auto& v : run_check("all", clean, o)) {
    // The synthetic sets have no constant-Z tables, and no scaling fit (so no phi_J for the
    // zeta check, no fitted parameters): nothing to compare there, inconclusive.
    const bool nothing_to_compare = v.case_name.find("constant Z") != std::string::npos ||
                                    v.check == "zeta" || v.check.starts_with("fit_");
    BOOST_TEST(v.status == (nothing_to_compare ? "inconclusive" : "pass"),
               v.check << " " << v.case_name << ": " << v.reason);
    passed += v.status == "pass";
  }
  BOOST_TEST(passed == 2 + 2 + 2);  // finite size (phi), sample pairs, phi_init at two rates
  int failed = 0;
  for (const auto& v : run_check("all", planted, o)) {
    const bool should_fail = v.case_name.find("rate 1e-3") != std::string::npos &&
                             v.case_name.find("constant Z") == std::string::npos;
    if (should_fail)
      BOOST_TEST(v.status == "fail", v.check << " " << v.case_name << ": " << v.reason);
    failed += v.status == "fail";
  }
  BOOST_TEST(failed == 3);  // finite size, sample pairs and phi_init at rate 1e-3
  // Named run sets: the same size at two rates that differ by 50% (a planted change of rate),
  // judged at a 10% margin: Delta p/p 0.4, surely beyond it (the bound about 0.4 - 0.1).
  o.margins["finite_size"] = 0.1;
  StatsData rates;
  rates.ensembles.push_back(ensemble(1024, 0.6, -3.0, runs(10, 0.0, rng)));
  rates.ensembles.push_back(ensemble(1024, 0.6, -4.0, runs(10, 0.5, rng)));
  o.set_a = RunSetSelector::parse("n=1024,rate=-3");
  o.set_b = RunSetSelector::parse("rate=-4");
  const auto v = finite_size_check(rates, o);
  BOOST_TEST_REQUIRE(!v.empty());
  BOOST_TEST(v.front().status == "fail");
  BOOST_CHECK_THROW(RunSetSelector::parse("size=3"), std::invalid_argument);
}

BOOST_AUTO_TEST_CASE(jamming_points_compared_across_phi_init) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g(0.0, 0.003);  // sample spread of phi_Ji at these sizes
  auto points = [&](double mean) {
    std::vector<double> v;
    for (int s = 0; s < 10; ++s) v.push_back(mean + g(rng));
    v[3] = NAN;  // a run that did not bracket its jamming point is left out
    return v;
  };
  // False alarms over 300 repeats of equal means: near alpha = 0.05.
  int alarms = 0;
  for (int r = 0; r < 300; ++r)
    alarms +=
        compare_means(points(0.84), points(0.84), Levels::two_sided(0.05), 400, r).p_value <= 0.05;
  BOOST_TEST_MESSAGE("phi_J test: measured false-alarm rate " << alarms / 300.0);
  BOOST_TEST(alarms / 300.0 > 0.015);
  BOOST_TEST(alarms / 300.0 < 0.095);
  StatsData d;
  for (double phi_init : {0.6, 0.7, 0.8}) {
    auto e = ensemble(1024, phi_init, -4.0, runs(10, 0.0, rng));
    e.jamming_points = points(phi_init == 0.8 ? 0.856 : 0.840);  // planted: 0.8 jams later
    d.ensembles.push_back(e);
  }
  CheckOptions o;
  o.permutations = 500;
  o.phi_min = 0.80;
  o.margins["phi_init"] = 0.3;
  // Spread 0.003 and 9 values per set exclude <phi_Ji> differences above about 0.005; the
  // planted 0.016 lies beyond 0.008 by about three of its errors (0.0014), so it surely
  // exceeds it.
  o.margins["jamming_point"] = 0.008;
  int jamming_verdicts = 0;
  for (const auto& v : phi_init_check(d, o)) {
    if (v.case_name.find("phi_Ji") == std::string::npos) continue;
    ++jamming_verdicts;
    const bool planted = v.case_name.find("phi_init 0.8") != std::string::npos;
    BOOST_TEST(v.status == (planted ? "fail" : "pass"), v.case_name << ": " << v.reason);
  }
  BOOST_TEST(jamming_verdicts == 2);
}

BOOST_AUTO_TEST_CASE(json_and_junit_are_valid_and_exit_status_follows_failures) {
  Verdict pass;
  pass.check = "finite_size";
  pass.case_name = "a <vs> b & \"quoted\"";
  pass.status = "pass";
  pass.statistic = 1.0;
  Verdict fail = pass;
  fail.status = "fail";
  fail.reason = "p = 0.001 < 'alpha'";
  const Verdict skip = inconclusive("phi_init", "all", "single phi_init");
  BOOST_TEST(exit_status({pass}) == 0);
  BOOST_TEST(exit_status({pass, skip}) == 3);
  BOOST_TEST(exit_status({pass, fail, skip}) == 1);
  Verdict expected = fail;
  expected.expected_failure = true;
  BOOST_TEST(exit_status({pass, expected}) == 0);
  BOOST_TEST(exit_status({pass, expected, skip}) == 3);
  const auto file = nlohmann::json::parse(to_json({pass, fail, skip}, "demo"));
  BOOST_TEST(file["schema_version"] == kChecksSchemaVersion);
  BOOST_TEST(file["campaign"] == "demo");
  BOOST_TEST(file["created"].get<std::string>().size() == 20u);  // 2026-11-23T01:02:03Z
  const auto json = file["verdicts"];
  BOOST_TEST(json.size() == 3u);
  BOOST_TEST(json[1]["status"] == "fail");
  BOOST_TEST(json[2]["statistic"].is_null());  // NaN is written as null, not as invalid JSON
  // Read back through the one reader (verdict_file.hpp): every field as written.
  const VerdictFile back = parse_verdict_file(to_json({pass, fail, skip}, "demo"), "demo.json");
  BOOST_TEST(back.campaign == "demo");
  BOOST_TEST(back.verdicts.size() == 3u);
  BOOST_TEST(back.verdicts[0].case_name == pass.case_name);
  BOOST_TEST(back.verdicts[1].reason == fail.reason);
  BOOST_TEST(std::isnan(back.verdicts[2].statistic));
  BOOST_TEST(back.tables[1].has_value());
  BOOST_TEST(back.tables[1]->status == "fail");
  const auto dir =
      std::filesystem::temp_directory_path() / ("jam-junit-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "checks.xml") << to_junit_xml({pass, fail, skip}, "jam.check.all");
  const std::string script =
      "import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); "
      "assert r.get('failures') == '1' and r.get('skipped') == '1' and "
      "len(r.findall('testcase')) == 3 and len(r.findall('testcase/failure')) == 1";
  BOOST_TEST(jam::run_program({"python3", "-c", script, (dir / "checks.xml").string()}) == 0);
  std::filesystem::remove_all(dir);
}
