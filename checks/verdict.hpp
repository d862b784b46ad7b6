#pragma once
// A check's verdict, as CI acts on it and a physicist reads it, judged against a margin M on
// the effect (checks/margin.hpp):
//   pass          the effects the data allow (at 1 - alpha) lie within +-M: excluded_above <= M
//                 (even when a smaller difference is detected; the reason says so);
//   fail          the effect surely exceeds the margin: the data exclude every effect at or
//                 below M (excluded_below > M, at the detection level);
//   inconclusive  anything else: the data cannot tell (with samples_needed, an estimate of how
//                 many samples per set would decide it), a difference detected but not shown
//                 to exceed M, or there was nothing to compare.
// With the statistic and its threshold and the smallest effect the data could have detected.
// Written as a table, as JSON and as JUnit XML (inconclusive as skipped).
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace jam::checks {

struct Verdict {
  std::string check;  // e.g. "finite_size", "sample_pairs", "phi_init"
  std::string
      case_name;  // what was compared, e.g. "n1024 vs n2048, phi_init 0.6, rate 1e-4, constant phi"
  std::string status;  // "pass", "fail" or "inconclusive"
  std::string reason;  // one line: what the numbers mean, or why nothing could be decided
  std::string statistic_name;
  double statistic = NAN;
  double threshold = NAN;
  double detectable = NAN;        // smallest effect the data could have detected
  double excluded_above = NAN;    // effects larger than this are excluded (where meaningful)
  double excluded_below = NAN;    // effects at or below this are excluded: the effect surely
                                  // exceeds it (0 when nothing is detected)
  double estimate = NAN;          // the signed effect measured, in the unit of the margin
  // Where along the compression the verdict judges (checks/regions.hpp): "pooled" (a range
  // stated in the reason), "below", "at" or "above" jamming; empty for verdicts that are not
  // about a stretch of the compression (fits, jamming points, LAMMPS).
  std::string region;
  double margin = NAN;            // M: the largest effect that still passes
  double samples_needed = NAN;    // inconclusive: samples per set that would decide (est.)
  bool expected_failure = false;  // the campaign marks this verdict as expected to fail
  // The unit of detectable, excluded_above and margin when it is not the check's margin unit
  // (check_registry.hpp): e.g. "d_s" for the lammps check's positions. Empty: the check's.
  std::string unit;
  // The rule that decided the status, in words (the tables show it after "decided by"), e.g.
  // "the pointwise rule at phi 0.8123, the numbers that point's": the estimate and bounds are
  // then that rule's. Empty: the statistic named above against its threshold (table_row).
  std::string rule;
  // The variable of the range judged (values range_min, range_max): "phi" or "Z"; empty: phi.
  std::string range_variable;
  std::map<std::string, double> values;  // further numbers a later stage reads (JSON "values")
  // Curves behind the verdict, for the report (checks.h5): e.g. "grid", "delta", "sigma".
  std::vector<std::pair<std::string, std::vector<double>>> curves;
};

/// A verdict that could not be reached (nothing to compare), and why.
inline Verdict inconclusive(const std::string& check, const std::string& case_name,
                            const std::string& reason) {
  Verdict v;
  v.check = check;
  v.case_name = case_name;
  v.status = "inconclusive";
  v.reason = reason;
  return v;
}

/// The unit of v's effects (detectable, excluded_above, margin): "relative" (a relative
/// difference, written in %), "packing_fraction" (the check's registry entry says which), or
/// v.unit when set. A check the registry does not know: "relative".
std::string effect_unit(const Verdict& v);

/// An effect of v as words give it, in its unit: "4.1%" (relative), "0.0012" (packing
/// fraction), "6.6e-12 d_s" (another unit); with a sign when `sign`. "-" when not finite.
std::string effect_text(const Verdict& v, double x, bool sign = false);
/// The same in a named unit ("relative", "packing_fraction", or a unit's name).
std::string effect_text(const std::string& unit, double x, bool sign = false);

/// What the terminal shows of a verdict's reason: its first clause (up to the first ": ", "; ",
/// " (" or " | "), or for an inconclusive verdict with an estimate, the samples that would
/// decide it. The whole reason is in checks.json and the report.
std::string short_reason(const Verdict& v);

/// What every table of verdicts shows of one (the terminal's, the report's, JUnit's): the one
/// definition of each cell, written into checks.json as the verdict's `table` object, which the
/// report reads instead of computing its own. Numbers in the verdict's effect unit (`unit`
/// names it: "%", "packing fraction" or the unit's name; relative effects in %), "-" where
/// there is none.
struct TableRow {
  std::string status;  // "pass", "fail", "inconclusive", or with " (expected)"
  std::string case_name;
  std::string unit;      // the words after "effects in"
  std::string estimate;  // the signed effect measured: "+17.2"
  // The effects the data allow, |effect|: "12.1..25" (at or below 12.1 and above 25 excluded),
  // "<= 4.69" (nothing detected: only the bound above), "> 12.1" (no bound above).
  std::string allowed;
  std::string margin;
  std::string range;    // the range judged: "phi 0.8123..0.8712", "Z 4.1..4.5"; "-": none
  std::string region;   // checks.json `region` as it is (pooled, below, at, above, ...); "-"
  std::string samples;  // samples per set, "4, 4" (first set, second); "-" when unknown
  std::string rule;     // which rule decided, with its numbers; "" when nothing was judged
  std::string reason;   // short_reason
};
TableRow table_row(const Verdict& v);
/// The row as checks.json's `table` object (reference/schema.md), and back (throws
/// nlohmann::json::exception on a missing key).
nlohmann::json to_json(const TableRow& row);
TableRow table_row_from_json(const nlohmann::json& j);

/// The terminal table (checks/verdict_table.cpp): per check, in order of first appearance, a
/// heading line with its counts and the unit of its effects, a column header, and per verdict
/// a line of its numbers (status, estimate, |effect| allowed, margin, range judged, region,
/// samples per set), then its whole case name and its short reason with the rule that decided
/// it, on one line when that fits in kTableWidth columns, else folded onto lines of their own
/// (a case name is never cut). Relative effects in %.
/// Then the counts of all verdicts. reports/report_html.py lays out the same rows the same way
/// (tests/test_verdict_table.cpp compares them line for line).
constexpr std::size_t kTableWidth = 100;
std::string format_table(const std::vector<Verdict>& verdicts);
/// Exit status of `jam check`: 1 if any verdict failed (other than an expected failure), else
/// 3 if any is inconclusive, else 0. (2 is a check that could not run: a tool error.)
int exit_status(const std::vector<Verdict>& verdicts);

/// Counts of the three outcomes, expected failures apart: "12 passed, 1 failed (expected),
/// 3 inconclusive".
std::string outcome_counts(const std::vector<Verdict>& verdicts);

}  // namespace jam::checks
