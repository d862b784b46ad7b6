// The printed summary of a scaling-fit scan (stats/scan_failures.hpp, `jam stats` and
// `jam pipeline`): failed rows are folded into one line of distinct reasons with their counts,
// never one line per row; a scan that failed everywhere is one line.
#include <boost/test/unit_test.hpp>
#include <string>

#include "stats/campaign_stats.hpp"
#include "stats/scan_failures.hpp"

using namespace jam::stats;

namespace {

ScanRow failed(double rate_max, double half_window, const std::string& why) {
  ScanRow r;
  r.rate_max = rate_max;
  r.half_window = half_window;
  r.failure = why;
  return r;
}

ScanRow fitted(double rate_max, double half_window) {
  ScanRow r = failed(rate_max, half_window, "");
  r.result = ScalingFitResult{};
  r.result->phi_j = 0.8412;
  r.result->quality = "ok";
  return r;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// The lines of `text` from the one containing `from` to the next blank line.
std::string section(const std::string& text, const std::string& from) {
  const auto start = text.rfind('\n', text.find(from)) + 1;
  const auto end = text.find("\n\n", start);
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start + 1);
}

const std::string kTwoRates =
    "fit: 2 rate(s) at or below rate_max {}; a scaling fit needs at least 3 (with 2, phi_J "
    "and q trade off)";

std::string two_rates(const char* rate_max) {
  std::string s = kTwoRates;
  return s.replace(s.find("{}"), 2, rate_max);
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_scan_that_failed_everywhere_is_one_line) {
  CampaignStats s;
  s.data.name = "small";
  for (double half : {0.01, 0.02, 0.03})
    for (const char* rm : {"0.00316", "0.001"})
      s.fit.rows.push_back(failed(std::stod(rm), half, two_rates(rm)));
  s.fit.failure = s.fit.rows.back().failure;
  s.fit_z = s.fit;
  const std::string out = format_stats_summary(s);
  BOOST_TEST(count(out, "fit failed") == 0u, out);
  BOOST_TEST(count(out, "rate(s) at or below") == 2u, out);  // once per scan (phi and Z)
  const std::string phi = section(out, "scaling fit at constant phi");
  BOOST_TEST(count(phi, "\n") == 1u, phi);
  BOOST_TEST(phi.find("none of the 6 fits could be made (6 rows, e.g.: 2 rate(s) at or below "
                      "rate_max 0.00316; a scaling fit needs at least 3") != std::string::npos,
             phi);
  BOOST_TEST(section(out, "scaling fit at constant Z").find("none of the 6 fits") !=
             std::string::npos);
}

BOOST_AUTO_TEST_CASE(distinct_reasons_are_named_once_with_their_counts) {
  FitScan scan;
  scan.rows = {failed(1e-3, 0.01, "fit: phi_J = 0.9 lies outside"),
               failed(1e-3, 0.02, "fit: phi_J = 0.91 lies outside"),
               failed(1e-4, 0.01, "fit ends on a bound: q = 1.2 (0 < q < 1)"),
               failed(1e-4, 0.02, "fit: phi_J = 0.9 lies outside")};
  const auto kinds = scan_failure_kinds(scan);
  BOOST_TEST_REQUIRE(kinds.size() == 2u);
  BOOST_TEST(kinds[0].reason == "phi_J = 0.9 lies outside");
  BOOST_TEST(kinds[0].rows == 3u);
  BOOST_TEST(kinds[0].numbers_differ);
  BOOST_TEST(kinds[1].rows == 1u);
  BOOST_TEST(!kinds[1].numbers_differ);
  BOOST_TEST(scan_failure_words(scan) ==
             "3 rows, e.g.: phi_J = 0.9 lies outside | 1 row: fit ends on a bound: q = 1.2 "
             "(0 < q < 1)");
}

BOOST_AUTO_TEST_CASE(the_fitted_rows_keep_their_table_and_the_failures_fold_below_it) {
  CampaignStats s;
  s.data.name = "partial";
  s.fit.rows = {fitted(1e-5, 0.01), failed(1e-6, 0.01, two_rates("1e-06")), fitted(1e-5, 0.02),
                failed(1e-6, 0.02, two_rates("1e-06"))};
  s.fit.failure = "no fit of quality ok";
  const std::string out = format_stats_summary(s);
  const std::string phi = section(out, "scaling fit at constant phi");
  BOOST_TEST(count(phi, "0.84120(") == 2u, phi);  // one line per fitted row
  BOOST_TEST(count(phi, "rate(s) at or below") == 1u, phi);
  BOOST_TEST(phi.find("not fitted: 2 of the 4 rows (2 rows: 2 rate(s) at or below rate_max "
                      "1e-06;") != std::string::npos,
             phi);
  BOOST_TEST(count(out, "fit failed") == 0u, out);
}
