// The verdicts as a person reads them on the terminal (checks/verdict_table.cpp): one table per
// check, each under one heading line with its counts and the unit of its effects; case names
// whole, however long; each number in one unit (relative effects in %, in the rows as in the
// reasons that reach the terminal, never beside a fraction); a short reason per row, the
// whole one left to checks.json and the report. Every verdict shows its estimate with its sign,
// the effects the data allow, the margin, the range judged and its region, the samples per set
// and the rule that decided it; in 100 columns. The same cells in checks.json (`table`), in
// JUnit and in the report's tables (tests/verdict_table_report.py, run from here).
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "checks/margin.hpp"
#include "checks/pooled_verdict.hpp"
#include "checks/verdict.hpp"
#include "checks/verdict_file.hpp"
#include "sim/io/process.hpp"

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

/// The lines of the verdict of the case named `case_name`: its numbers, then its case and
/// reason (one line, or the case and then the reason on one line or more). Empty when there is
/// no such verdict.
std::vector<std::string> block_of(const std::string& text, const std::string& case_name) {
  const std::vector<std::string> all = lines(text);
  for (std::size_t i = 1; i < all.size(); ++i) {
    if (all[i].rfind("    " + case_name + ": ", 0) == 0) return {all[i - 1], all[i]};
    if (all[i] != "    " + case_name) continue;
    std::vector<std::string> block = {all[i - 1], all[i]};
    for (std::size_t k = i + 1; k < all.size() && all[k].rfind("    ", 0) == 0; ++k)
      block.push_back(all[k]);
    return block;
  }
  return {};
}

/// The numbers line of the case named `case_name`.
std::string row_of(const std::string& text, const std::string& case_name) {
  const auto b = block_of(text, case_name);
  return b.empty() ? "" : b.front();
}

/// The short reason of the case named `case_name`, with the rule that decided it.
std::string reason_of(const std::string& text, const std::string& case_name) {
  const auto b = block_of(text, case_name);
  if (b.size() == 2) return b[1].substr(4 + case_name.size() + 2);
  std::string out;
  for (std::size_t k = 2; k < b.size(); ++k) out += (k > 2 ? " " : "") + b[k].substr(4);
  return out;
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
  BOOST_TEST(block_of(table, long_case).size() >= 3u, table);
  BOOST_TEST(table.find("...") == std::string::npos, table);
  // The short reason: the outcome's clause, not the numbers and details after it.
  BOOST_TEST(reason_of(table, "n256 vs n1024, phi_init 0.4, rate 1e-8, constant Z") ==
                 "the effect surely exceeds the margin",
             table);
  BOOST_TEST(reason_of(table, "all") == "stats.h5 has no representative scaling fit", table);
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
  // The relative row: 7.73 and 10 (percent, bare: the heading names the unit), no fraction.
  const std::string relative = row_of(table, "a vs b");
  BOOST_TEST(std::regex_search(relative, std::regex(R"(<= 7\.73 +10 )")), relative);
  BOOST_TEST(!has_fraction(relative), relative);
  BOOST_TEST(relative.find('%') == std::string::npos, relative);
  // The packing row: packing differences as they are.
  const std::string absolute = row_of(table, "c vs d");
  BOOST_TEST(std::regex_search(absolute, std::regex(R"(<= 0\.0051 +0\.005 )")), absolute);
  // A unit of the verdict's own (the lammps check's positions) is named before its rows.
  Verdict positions = decided("lammps", "2D: positions", false, 6.6e-12, 1e-9);
  positions.unit = "d_s";
  Verdict pressure = decided("lammps", "2D: pressure", false, 1.4e-9, 1e-5);
  const std::string lammps = format_table({positions, pressure});
  BOOST_TEST(starting(lammps, "lammps:").size() == 1u, lammps);
  BOOST_TEST(lammps.find("  effects in %:\n") < lammps.find("  effects in d_s:\n"), lammps);
  BOOST_TEST(row_of(lammps, "2D: pressure").find(" 0.001 ") != std::string::npos, lammps);
  BOOST_TEST(row_of(lammps, "2D: positions").find(" 1e-09 ") != std::string::npos, lammps);
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
             "about 93 samples per set would decide; cheapest: 4 of the first set, 129 of the "
             "second");
  BOOST_TEST(table_row(estimate).samples == "3, 129");
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

namespace {

/// A pooled verdict as the pressure checks write it: its range, samples and region.
Verdict pooled_verdict(const std::string& case_name, const std::string& region, double estimate,
                       double excluded_above, double margin) {
  Verdict v = decided("finite_size", case_name, false, excluded_above, margin);
  v.estimate = estimate;
  v.region = region;
  v.statistic_name = "|weighted mean Delta p/p|";
  v.statistic = std::abs(estimate);
  v.rule = "the weighted mean over the range";
  v.values = {{"range_min", 0.8123}, {"range_max", 0.8712}, {"samples_a", 4}, {"samples_b", 6}};
  return v;
}

/// Two sets of 6 runs on 20 points, alike (within 0.2%) but at one point, where the first is
/// 1.5 times the second: the weighted mean stays within a 10% margin, the pointwise rule fails.
Verdict pointwise_fail() {
  Aligned al;
  for (int k = 0; k < 20; ++k) al.grid.push_back(0.80 + 0.002 * k);
  for (int s = 0; s < 6; ++s) {
    std::vector<double> a, b;
    for (int k = 0; k < 20; ++k) {
      const double wobble = 1 + 0.001 * ((s * 7 + k * 3) % 5 - 2);
      a.push_back((k == 12 ? 1.5 : 1.0) * wobble);
      b.push_back(wobble * (1 + 0.001 * ((s + k) % 3 - 1)));
    }
    al.a.push_back(a);
    al.b.push_back(b);
  }
  PoolRange range;
  range.why = "the planted grid";
  Verdict v;
  v.check = "finite_size";
  v.case_name = "n256 vs n1024, phi_init 0.4, rate 1e-6, constant phi";
  v.region = "pooled";
  judge_pooled(v, al, range, {0.05, 0.05}, 0.10, 400);
  return v;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

BOOST_AUTO_TEST_CASE(every_verdict_shows_estimate_interval_margin_range_region_and_samples) {
  Verdict pass = pooled_verdict("n256 vs n1024, phi_init 0.4, rate 1e-6, constant phi", "pooled",
                                0.0123, 0.0469, 0.05);
  Verdict below = pooled_verdict(
      "n256 vs n1024, phi_init 0.4, rate 1e-6, constant phi, below "
      "jamming",
      "below", -0.0211, 0.0802, 0.05);
  const std::string table = format_table({pass, below});
  BOOST_TEST_MESSAGE(table);
  // status, the signed estimate, the effects allowed, the margin, the range, region, samples.
  const std::regex numbers(
      R"(^  pass +\+1\.23  <= 4\.69 +5  phi 0\.8123\.\.0\.8712  pooled  4, 6$)");
  BOOST_TEST(std::regex_search(row_of(table, pass.case_name), numbers), table);
  BOOST_TEST(row_of(table, below.case_name).find(" -2.11 ") != std::string::npos, table);
  BOOST_TEST(row_of(table, below.case_name).find(" below ") != std::string::npos, table);
  BOOST_TEST(reason_of(table, pass.case_name) ==
                 "within the margin; decided by the weighted mean over the range",
             table);
  // A detected effect shows its interval; one with no bound above, the bound below.
  Verdict detected = decided("finite_size", "x", true, 0.30, 0.10, 0.12);
  BOOST_TEST(table_row(detected).allowed == "12..30");
  detected.excluded_above = HUGE_VAL;
  BOOST_TEST(table_row(detected).allowed == "> 12");
  // Any region name, and a range in Z, as they are.
  Verdict asked = pass;
  asked.region = "asked";
  asked.range_variable = "Z";
  asked.values["range_min"] = 4.1;
  asked.values["range_max"] = 4.5;
  BOOST_TEST(table_row(asked).region == "asked");
  BOOST_TEST(table_row(asked).range == "Z 4.1..4.5");
  const std::string with_asked = format_table({pass, asked});
  BOOST_TEST(with_asked.find("pooled only") == std::string::npos, with_asked);
  // Nothing to show: "-", never "nan" or "inf".
  const TableRow none = table_row(inconclusive("zeta", "all", "nothing to compare"));
  for (const std::string& cell :
       {none.estimate, none.allowed, none.margin, none.range, none.region, none.samples})
    BOOST_TEST(cell == "-");
  BOOST_TEST(none.rule.empty());
}

// A pointwise fail once showed only "excluded above 4.69, margin 5": it now names the rule
// that decided and where, and its numbers are that rule's (the effect surely beyond the margin).
BOOST_AUTO_TEST_CASE(a_pointwise_fail_names_its_rule_and_shows_its_numbers) {
  const Verdict v = pointwise_fail();
  BOOST_TEST_REQUIRE(v.status == "fail", v.reason);
  const TableRow row = table_row(v);
  BOOST_TEST(row.rule == "the pointwise rule at phi 0.8240, the numbers that point's", row.rule);
  // The interval lies wholly beyond the margin: its lower end exceeds 10 (%).
  std::smatch m;
  BOOST_TEST_REQUIRE(std::regex_match(row.allowed, m, std::regex(R"(([0-9.]+)\.\.([0-9.e+]+))")),
                     row.allowed);
  BOOST_TEST(std::stod(m[1]) > 10.0, row.allowed);
  BOOST_TEST(std::stod(row.estimate) > std::stod(m[1]), row.estimate);
  BOOST_TEST(row.range == "phi 0.8..0.838");
  BOOST_TEST(row.samples == "6, 6");
  const std::string table = format_table({v});
  const std::string reason = reason_of(table, v.case_name);
  BOOST_TEST(reason.starts_with("the effect surely exceeds the margin"), table);
  // Too long for one line with its reason: the rule on a line of its own.
  BOOST_TEST(table.find("\n    decided by the pointwise rule at phi 0.8240, the numbers that "
                        "point's\n") != std::string::npos,
             table);
  // Units in the heading, none in the rows (numbers, case, reason and rule).
  BOOST_TEST(table.find('%') == table.find("effects in %") + 11, table);
  BOOST_TEST(table.find('%', table.find('\n')) == std::string::npos, table);
}

BOOST_AUTO_TEST_CASE(the_table_keeps_to_100_columns) {
  std::vector<Verdict> verdicts;
  const std::string base = "n1024 vs n4096, phi_init 0.6, rate 1e-4.5, constant phi";
  for (const std::string region : {"pooled", "below", "at", "above", "asked"}) {
    Verdict v = pooled_verdict(region == "pooled" ? base : base + ", " + region + " jamming",
                               region, 0.171, 0.2473, 0.05);
    v.samples_needed = 129;
    v.status = "inconclusive";
    v.values["samples_needed_a"] = 4, v.values["samples_needed_b"] = 129;
    v.expected_failure = region == "at";
    verdicts.push_back(v);
  }
  verdicts.push_back(pointwise_fail());
  const std::string long_case(130, 'x');
  verdicts.push_back(decided("jamming_point", long_case, true, 0.2, 0.005, 0.1));
  const std::string table = format_table(verdicts);
  BOOST_TEST_MESSAGE(table);
  for (const auto& line : lines(table)) {
    // A case name longer than the table stands alone on its line, whole.
    if (line == "    " + long_case) continue;
    BOOST_TEST(line.size() <= kTableWidth, line.size() << ": " << line);
  }
  BOOST_TEST(table.find("    " + long_case + "\n") != std::string::npos, table);
}

// The cells are written once: checks.json carries them, JUnit gives them one a line, and the
// report lays out from checks.json the very lines `jam check` prints (the script also checks
// the report's HTML rows and its fallback for a checks.json without cells).
BOOST_AUTO_TEST_CASE(checks_json_junit_and_the_report_show_the_same_cells) {
  std::vector<Verdict> verdicts = {
      pooled_verdict("n256 vs n1024, phi_init 0.4, rate 1e-6, constant phi", "pooled", 0.0123,
                     0.0469, 0.05),
      pointwise_fail(),
      decided("jamming_point", "n256 rate 1e-4: <phi_Ji> at phi_init 0.6 vs 0.4", false, 0.0051,
              0.005),
      inconclusive("zeta", "all", "stats.h5 has no representative scaling fit: phi_J is unknown"),
  };
  Verdict asked = verdicts[0];
  asked.region = "asked", asked.case_name += ", asked", asked.range_variable = "Z";
  asked.expected_failure = true;
  verdicts.push_back(asked);
  Verdict positions = decided("lammps", "2D: positions", false, 6.6e-12, 1e-9);
  positions.unit = "d_s";
  verdicts.push_back(positions);
  verdicts.push_back(decided("lammps", "2D: pressure", false, 1.4e-9, 1e-5));

  const auto dir =
      std::filesystem::temp_directory_path() / ("jam-verdict-table-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "checks.json") << to_json(verdicts, "planted");
  std::ofstream(dir / "table.txt") << format_table(verdicts);
  std::ofstream(dir / "checks.xml") << to_junit_xml(verdicts, "jam.check.all");

  const auto json = nlohmann::json::parse(read_file(dir / "checks.json"));
  for (std::size_t k = 0; k < verdicts.size(); ++k) {
    const TableRow r = table_row(verdicts[k]),
                   back = table_row_from_json(json["verdicts"][k]["table"]);
    BOOST_TEST(back.reason == r.reason);
    BOOST_TEST(back.allowed == r.allowed);
    BOOST_TEST(back.range == r.range);
    BOOST_TEST(back.rule == r.rule);
    BOOST_TEST(json["verdicts"][k]["table"] == to_json(r));
  }
  const std::string xml = read_file(dir / "checks.xml");
  for (const auto& v : verdicts) {
    const TableRow r = table_row(v);
    std::string expected = "estimate: " + r.estimate + "\n|effect|: " + r.allowed;
    expected = std::regex_replace(expected, std::regex("<"), "&lt;");
    expected = std::regex_replace(expected, std::regex(">"), "&gt;");
    BOOST_TEST(xml.find(expected) != std::string::npos, r.case_name);
  }
  const int status =
      jam::run_program({"/usr/bin/python3", JAM_SOURCE_DIR "/tests/verdict_table_report.py",
                        "--source", JAM_SOURCE_DIR, (dir / "checks.json").string(),
                        (dir / "table.txt").string(), (dir / "checks.xml").string()});
  BOOST_TEST(status == 0);
  std::filesystem::remove_all(dir);
}
