// The verdicts as a person reads them on the terminal (checks/verdict_table.cpp): one table per
// check, each under one heading line with its counts and the unit of its effects; case names
// whole, however long; each number in one unit (relative effects in %, in the rows as in the
// reasons that reach the terminal, never beside a fraction); a short reason per row, the
// whole one left to checks.json and the report.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "checks/margin.hpp"
#include "checks/verdict.hpp"

using namespace jam::checks;

namespace {

Verdict decided(const std::string& check, const std::string& case_name, bool detected,
                double excluded_above, double margin, double excluded_below = 0.0) {
  Verdict v;
  v.check = check;
  v.case_name = case_name;
  v.detectable = 0.05;
  decide(v, detected, excluded_above, excluded_below, margin);
  return v;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// The lines that begin with `start`.
std::vector<std::string> starting(const std::string& text, const std::string& start) {
  std::vector<std::string> out;
  for (const auto& l : lines(text))
    if (l.rfind(start, 0) == 0) out.push_back(l);
  return out;
}

/// The row of the case named `case_name`.
std::string row_of(const std::string& text, const std::string& case_name) {
  for (const auto& l : lines(text))
    if (l.find(case_name) != std::string::npos && l.rfind("  ", 0) == 0) return l;
  return "";
}

/// Numbers written as fractions below 1 ("0.172"), which a relative effect must not be.
bool has_fraction(const std::string& text) {
  return std::regex_search(text, std::regex(R"((^|[^0-9.])0\.[0-9])"));
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_heading_per_check_with_its_counts_and_whole_case_names) {
  const std::string planted(170, 'x');  // longer than any column a table might cut to
  const std::string long_case = "n1024 vs n2048, phi_init 0.6, rate 1e-4.5, " + planted;
  const std::vector<Verdict> verdicts = {
      decided("finite_size", long_case, false, 0.05, 0.1),
      decided("jamming_point", "n256 rate 1e-4: <phi_Ji> at phi_init 0.6 vs 0.4", false, 0.0051,
              0.005),
      decided("finite_size", "n256 vs n1024, phi_init 0.4, rate 1e-8, constant Z", true, 0.3, 0.1,
              0.2),
      inconclusive("zeta", "all", "stats.h5 has no representative scaling fit: phi_J is unknown"),
  };
  const std::string table = format_table(verdicts);
  BOOST_TEST_MESSAGE(table);
  // One heading per check, in order of first appearance, with that check's counts only.
  BOOST_TEST(starting(table, "finite_size:").size() == 1u, table);
  BOOST_TEST(starting(table, "jamming_point:").size() == 1u, table);
  BOOST_TEST(starting(table, "zeta:").size() == 1u, table);
  BOOST_TEST(table.find("finite_size: 2 verdicts, 1 passed, 1 failed, 0 inconclusive") == 0u,
             table);
  BOOST_TEST(table.find("zeta: 1 verdict, 0 passed, 0 failed, 1 inconclusive") != std::string::npos,
             table);
  BOOST_TEST(table.find("jamming_point:") < table.find("zeta:"));
  // The case whole, in a row; nothing cut.
  BOOST_TEST(row_of(table, long_case).find(long_case) != std::string::npos, table);
  BOOST_TEST(table.find("...") == std::string::npos, table);
  // The short reason: the outcome's clause, not the numbers and details after it.
  BOOST_TEST(row_of(table, "constant Z").ends_with("the effect surely exceeds the margin"), table);
  BOOST_TEST(
      row_of(table, "no representative").ends_with("  stats.h5 has no representative scaling fit"),
      table);
  BOOST_TEST(table.ends_with("4 verdicts, 1 passed, 1 failed, 2 inconclusive\n"), table);
}

BOOST_AUTO_TEST_CASE(relative_effects_in_percent_said_once_in_the_heading) {
  Verdict pass = decided("finite_size", "a vs b", false, 0.0773, 0.1);
  Verdict packing = decided("jamming_point", "c vs d", false, 0.0051, 0.005);
  const std::string table = format_table({pass, packing});
  BOOST_TEST_MESSAGE(table);
  BOOST_TEST(starting(table, "finite_size:").front().ends_with("; effects in %"), table);
  BOOST_TEST(starting(table, "jamming_point:").front().ends_with("; effects in packing fraction"),
             table);
  // The relative row: 5, 7.73 and 10 (percent, bare: the heading names the unit), no fraction.
  const std::string relative = row_of(table, "a vs b");
  BOOST_TEST(std::regex_search(relative, std::regex(R"( 5 +7\.73 +10 )")), relative);
  BOOST_TEST(!has_fraction(relative), relative);
  BOOST_TEST(relative.find('%') == std::string::npos, relative);
  // The packing row: packing differences as they are.
  const std::string absolute = row_of(table, "c vs d");
  BOOST_TEST(std::regex_search(absolute, std::regex(R"( 0\.05 +0\.0051 +0\.005 )")), absolute);
  // A unit of the verdict's own (the lammps check's positions) is named before its rows.
  Verdict positions = decided("lammps", "2D: positions", false, 6.6e-12, 1e-9);
  positions.unit = "d_s";
  Verdict pressure = decided("lammps", "2D: pressure", false, 1.4e-9, 1e-5);
  const std::string lammps = format_table({positions, pressure});
  BOOST_TEST(starting(lammps, "lammps:").size() == 1u, lammps);
  BOOST_TEST(lammps.find("  effects in %:\n") < lammps.find("  effects in d_s:\n"), lammps);
  BOOST_TEST(row_of(lammps, "2D: pressure").find(" 0.001 ") != std::string::npos, lammps);
}

BOOST_AUTO_TEST_CASE(reasons_give_relative_effects_in_percent) {
  for (const auto& [detected, excluded] :
       {std::pair{false, 0.0773}, {true, 0.172}, {false, 0.172}, {false, HUGE_VAL}}) {
    const Verdict v = decided("finite_size", "a vs b", detected, excluded, 0.1);
    BOOST_TEST(!has_fraction(v.reason), v.reason);
    BOOST_TEST(v.reason.find("margin 10%") != std::string::npos, v.reason);
    if (std::isfinite(excluded))
      BOOST_TEST(v.reason.find(excluded < 0.1 ? "7.73%" : "17.2%") != std::string::npos, v.reason);
    // The row's short reason is the clause before the numbers.
    BOOST_TEST(short_reason(v).find_first_of("0123456789%") == std::string::npos, short_reason(v));
  }
  const Verdict packing = decided("jamming_point", "c vs d", false, 0.0051, 0.005);
  BOOST_TEST(packing.reason.find("effects up to 0.0051 allowed, margin 0.005") != std::string::npos,
             packing.reason);
  BOOST_TEST(packing.reason.find('%') == std::string::npos, packing.reason);
  BOOST_TEST(effect_text("relative", -1.622, true) == "-162%");
  BOOST_TEST(effect_text("packing_fraction", 0.0012) == "0.0012");
  BOOST_TEST(effect_text("d_s", 6.6e-12) == "6.6e-12 d_s");
  // An inconclusive verdict with an estimate: the samples that would decide it.
  Verdict estimate = decided("finite_size", "a vs b", false, 0.172, 0.1);
  estimate.samples_needed = 93;
  BOOST_TEST(short_reason(estimate) == "about 93 samples per set would decide");
  // With the cheapest split known, each side's count beside what it has: a cheap set of 3 and
  // a reference of 129 need one more of the first, not about 127 more of each.
  estimate.values["samples_needed_a"] = 4;
  estimate.values["samples_needed_b"] = 129;
  estimate.values["samples_a"] = 3;
  estimate.values["samples_b"] = 129;
  BOOST_TEST(short_reason(estimate) ==
             "about 93 samples per set would decide; cheapest: 4 of the first set (has 3), 129 of "
             "the second (has 129)");
}

BOOST_AUTO_TEST_CASE(a_check_judged_pooled_only_says_so_under_its_heading) {
  Verdict pooled = decided("finite_size", "a vs b", false, 0.05, 0.1);
  pooled.region = "pooled";
  const std::string only = format_table({pooled});
  BOOST_TEST(only.find("pooled only: no region around jamming judged") != std::string::npos, only);
  Verdict below = pooled;
  below.region = "below";
  below.case_name += ", below jamming";
  const std::string both = format_table({pooled, below});
  BOOST_TEST(both.find("pooled only") == std::string::npos, both);
  // Verdicts about no stretch of the compression (fits, LAMMPS) carry no region: no line.
  const std::string fits = format_table({decided("fit_parameters", "x", false, 0.05, 0.1)});
  BOOST_TEST(fits.find("pooled only") == std::string::npos, fits);
}
