// The verdicts an --until-decided sequence has decided, as its state (until-decided.json)
// keeps them (design/until_decided_state.hpp): each in its checks.json form, written by the
// one verdict writer (checks::verdict_json) with the look that decided it, and given back to
// a later look's verdict of the same identity; the states of earlier jams (their own field
// list, "detectable") are read too.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "checks/verdict_file.hpp"
#include "design/until_decided_state.hpp"

using namespace jam;
using nlohmann::json;

namespace {

checks::Verdict decided_verdict() {
  checks::Verdict v;
  v.check = "fit_parameters";
  v.case_name = "exponents, n256 vs n1024, phi_init 0.4";
  v.status = "pass";
  v.reason = "beta and y agree within 10% [look 2, alpha 0.0125]";
  v.statistic = 1.5, v.threshold = 2.5, v.estimate = 0.01, v.detectable = 0.04;
  v.excluded_above = 0.05, v.excluded_below = -0.05;
  v.values = {{"n_a", 256},        {"n_b", 1024}, {"phi_init_a", 0.4},
              {"phi_init_b", 0.4}, {"look", 2},   {"look_alpha", 0.0125}};
  return v;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_decided_verdict_is_kept_in_its_checks_json_form) {
  design::State s;
  const checks::Verdict v = decided_verdict();
  design::record_decided(s, "fit_parameters n_a=256", v, 2);
  json expected = checks::verdict_json(v);
  expected["look"] = 2;
  BOOST_TEST(s.decided["fit_parameters n_a=256"] == expected);
  // A later look's verdict of the same identity: the decision stands, its numbers the
  // deciding look's, its data this look's.
  checks::Verdict later = v;
  later.status = "inconclusive";
  later.reason = "not decided";
  later.statistic = later.detectable = later.excluded_above = NAN;
  later.samples_needed = 40;
  later.case_name = "exponents, n256 vs n1024, phi_init 0.4 (window moved)";
  design::restore_decided(s.decided["fit_parameters n_a=256"], later);
  BOOST_TEST(later.status == "pass");
  BOOST_TEST(later.reason == v.reason);
  BOOST_TEST(later.statistic == 1.5);
  BOOST_TEST(later.detectable == 0.04);
  BOOST_TEST(later.excluded_above == 0.05);
  BOOST_TEST(std::isnan(later.samples_needed));
  BOOST_TEST(later.values.at("look") == 2);
  BOOST_TEST(later.case_name == "exponents, n256 vs n1024, phi_init 0.4 (window moved)");
}

BOOST_AUTO_TEST_CASE(a_state_of_an_earlier_jam_is_read) {
  const json old = {{"look", 3},
                    {"status", "fail"},
                    {"reason", "differ: beta"},
                    {"statistic", 4.0},
                    {"threshold", 2.0},
                    {"excluded_above", nullptr},
                    {"excluded_below", 0.2},
                    {"estimate", 0.3},
                    {"detectable", 0.07}};
  checks::Verdict v = decided_verdict();
  design::restore_decided(old, v);
  BOOST_TEST(v.status == "fail");
  BOOST_TEST(v.reason == "differ: beta");
  BOOST_TEST(v.detectable == 0.07);
  BOOST_TEST(std::isnan(v.excluded_above));
  BOOST_TEST(v.excluded_below == 0.2);
  BOOST_TEST(v.values.at("look") == 3);
}
