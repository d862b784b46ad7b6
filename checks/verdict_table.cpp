// The words of verdicts on the terminal: each effect in one unit (relative effects in %, the
// same in the reasons as in the table), and the table `jam check` prints, one per check. The
// cells of a verdict's row are defined here once (table_row); checks.json carries them, and
// the report and JUnit show the same strings.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "checks/check_registry.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {
namespace {

/// The line under a check's heading when it judged no region around jamming
/// (reports/report_html.py prints the same).
constexpr const char* kPooledOnly =
    "  pooled only: no region around jamming judged (no phi_J: no scaling fit, no jamming "
    "points, no --phi-j)";
/// ... when, besides, the pooled range is the whole compression (no fit window, no range
/// asked): the verdicts answer a question over everything compressed, said before the rows.
constexpr const char* kPooledWhole =
    "  POOLED OVER THE WHOLE COMPRESSION: no range asked ([question] phi_min, phi_max) and no "
    "region around jamming (no scaling fit, no jamming points, <Z> does not cross 2D, no "
    "--phi-j); each reason says why";

/// The words after "effects in": "%", "packing fraction", or the verdict's own unit.
std::string unit_words(const std::string& unit) {
  if (unit == "relative") return "%";
  if (unit == "packing_fraction") return "packing fraction";
  return unit;
}

/// A table's number, in its table's unit (the heading names it), signed when `sign`.
std::string table_number(double x, bool percent, bool sign = false) {
  if (!std::isfinite(x)) return "-";
  return fmt::format(fmt::runtime(sign ? "{:+.3g}" : "{:.3g}"), percent ? 100 * x : x);
}

std::string status_text(const Verdict& v) {
  return v.expected_failure ? v.status + " (expected)" : v.status;
}

double value_of(const Verdict& v, const char* key) {
  const auto it = v.values.find(key);
  return it == v.values.end() ? NAN : it->second;
}

/// The effects the data allow, |effect| between what is excluded below and above.
std::string allowed_text(const Verdict& v, bool percent) {
  const bool low = std::isfinite(v.excluded_below) && v.excluded_below > 0;
  const bool high = std::isfinite(v.excluded_above);
  const std::string lo = table_number(v.excluded_below, percent),
                    hi = table_number(v.excluded_above, percent);
  if (low && high) return lo + ".." + hi;
  if (low) return "> " + lo;
  if (high) return "<= " + hi;
  return "-";
}

/// The range judged, "phi 0.8123..0.8712", from the values range_min and range_max.
std::string range_text(const Verdict& v) {
  const double lo = value_of(v, "range_min"), hi = value_of(v, "range_max");
  if (!std::isfinite(lo) && !std::isfinite(hi)) return "-";
  const auto end = [](double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : ""; };
  return fmt::format("{} {}..{}", v.range_variable.empty() ? "phi" : v.range_variable, end(lo),
                     end(hi));
}

std::string samples_text(const Verdict& v) {
  const double a = value_of(v, "samples_a"), b = value_of(v, "samples_b");
  if (std::isfinite(a) && std::isfinite(b)) return fmt::format("{:.0f}, {:.0f}", a, b);
  if (std::isfinite(a) || std::isfinite(b)) return fmt::format("{:.0f}", std::isfinite(a) ? a : b);
  return "-";
}

/// The rule that decided: the verdict's own words, else its statistic against its threshold.
std::string rule_text(const Verdict& v) {
  if (!v.rule.empty()) return v.rule;
  if (v.statistic_name.empty() || !std::isfinite(v.statistic)) return "";
  return fmt::format(
      "{} = {:.4g}{}", v.statistic_name, v.statistic,
      std::isfinite(v.threshold) ? fmt::format(", threshold {:.4g}", v.threshold) : std::string());
}

/// Verdicts of one check, grouped by the unit of their effects (in order of appearance).
struct CheckRows {
  std::string check;
  std::vector<std::pair<std::string, std::vector<const Verdict*>>> by_unit;
  std::vector<Verdict> all;  // for the counts
};

std::vector<CheckRows> by_check(const std::vector<Verdict>& verdicts) {
  std::vector<CheckRows> out;
  for (const auto& v : verdicts) {
    auto c =
        std::find_if(out.begin(), out.end(), [&](const auto& r) { return r.check == v.check; });
    if (c == out.end()) c = out.insert(out.end(), CheckRows{v.check, {}, {}});
    const std::string unit = effect_unit(v);
    auto u = std::find_if(c->by_unit.begin(), c->by_unit.end(),
                          [&](const auto& g) { return g.first == unit; });
    if (u == c->by_unit.end()) u = c->by_unit.insert(c->by_unit.end(), {unit, {}});
    u->second.push_back(&v);
    c->all.push_back(v);
  }
  // The check's own unit first (e.g. the lammps check's pressures before its positions).
  for (auto& c : out) {
    Verdict own;
    own.check = c.check;
    std::stable_partition(c.by_unit.begin(), c.by_unit.end(),
                          [&](const auto& g) { return g.first == effect_unit(own); });
  }
  return out;
}

std::string trimmed(std::string line) {
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line + "\n";
}

/// The widths of the columns of one check's table: the widest of header and cells.
struct Widths {
  std::size_t status = 7, estimate = 8, allowed = 8, margin = 6, range = 12, region = 6;
};

Widths widths_of(const std::vector<TableRow>& rows) {
  Widths w;
  for (const auto& r : rows) {
    w.status = std::max(w.status, r.status.size());
    w.estimate = std::max(w.estimate, r.estimate.size());
    w.allowed = std::max(w.allowed, r.allowed.size());
    w.margin = std::max(w.margin, r.margin.size());
    w.range = std::max(w.range, r.range.size());
    w.region = std::max(w.region, r.region.size());
  }
  return w;
}

std::string numbers_line(const Widths& w, const std::string& status, const std::string& estimate,
                         const std::string& allowed, const std::string& margin,
                         const std::string& range, const std::string& region,
                         const std::string& samples) {
  return trimmed(fmt::format("  {:<{}}  {:>{}}  {:<{}}  {:>{}}  {:<{}}  {:<{}}  {}", status,
                             w.status, estimate, w.estimate, allowed, w.allowed, margin, w.margin,
                             range, w.range, region, w.region, samples));
}

/// `text` on lines of at most kTableWidth columns, each led by four blanks, broken at blanks
/// (a word longer than a line stands alone on its line).
std::string wrapped(const std::string& text) {
  std::string out, line;
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    if (!line.empty() && 4 + line.size() + 1 + word.size() > kTableWidth) {
      out += "    " + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  return line.empty() ? out : out + "    " + line + "\n";
}

/// A verdict's rows: its numbers, then its case and reason on one line if it fits, else the
/// case whole on its line, then the reason and the rule on one line if they fit, else each
/// wrapped on lines of their own.
void verdict_rows(std::ostringstream& out, const Widths& w, const TableRow& r) {
  out << numbers_line(w, r.status, r.estimate, r.allowed, r.margin, r.range, r.region, r.samples);
  const std::string rule = r.rule.empty() ? "" : "decided by " + r.rule;
  const std::string why = rule.empty() ? r.reason : r.reason + "; " + rule;
  if (4 + r.case_name.size() + 2 + why.size() <= kTableWidth) {
    out << trimmed("    " + r.case_name + ": " + why);
    return;
  }
  out << trimmed("    " + r.case_name);
  if (4 + why.size() <= kTableWidth)
    out << trimmed("    " + why);
  else
    out << wrapped(r.reason) << wrapped(rule);
}

/// One check's table: heading, column header, rows (a line naming the unit before each group
/// when its effects come in more than one).
void check_table(std::ostringstream& out, const CheckRows& c) {
  std::vector<TableRow> rows;
  for (const auto& v : c.all) rows.push_back(table_row(v));
  const Widths w = widths_of(rows);
  const bool one_unit = c.by_unit.size() == 1;
  out << fmt::format("{}: {} verdict{}, {}{}\n", c.check, c.all.size(),
                     c.all.size() == 1 ? "" : "s", outcome_counts(c.all),
                     one_unit ? "; effects in " + unit_words(c.by_unit.front().first) : "");
  // A pressure check that judged no region but the pooled range says so before its rows.
  const bool pooled = std::any_of(c.all.begin(), c.all.end(),
                                  [](const Verdict& v) { return v.region == "pooled"; });
  const bool regions = std::any_of(c.all.begin(), c.all.end(), [](const Verdict& v) {
    return !v.region.empty() && v.region != "pooled";
  });
  const bool whole = std::any_of(c.all.begin(), c.all.end(), [](const Verdict& v) {
    return v.region == "pooled" && v.values.count("whole_compression");
  });
  if (pooled && !regions) out << (whole ? kPooledWhole : kPooledOnly) << "\n";
  out << numbers_line(w, "verdict", "estimate", "|effect|", "margin", "range judged", "region",
                      "samples");
  out << "    case: reason; decided by\n";
  for (const auto& [unit, group] : c.by_unit) {
    if (!one_unit) out << fmt::format("  effects in {}:\n", unit_words(unit));
    for (const Verdict* v : group) verdict_rows(out, w, table_row(*v));
  }
}

}  // namespace

std::string effect_unit(const Verdict& v) {
  if (!v.unit.empty()) return v.unit;
  const CheckEntry* e = find_check(v.check);
  return e && e->margin_unit == MarginUnit::packing_fraction ? "packing_fraction" : "relative";
}

std::string effect_text(const Verdict& v, double x, bool sign) {
  return effect_text(effect_unit(v), x, sign);
}

std::string effect_text(const std::string& unit, double x, bool sign) {
  if (!std::isfinite(x)) return "-";
  const std::string number =
      fmt::format(fmt::runtime(sign ? "{:+.3g}" : "{:.3g}"), unit == "relative" ? 100 * x : x);
  if (unit == "relative") return number + "%";
  if (unit == "packing_fraction") return number;
  return number + " " + unit;
}

std::string short_reason(const Verdict& v) {
  if (v.status == "inconclusive" && std::isfinite(v.samples_needed)) {
    // The cheapest split per side ("129 per set" read alone sends a user to run 127 more of
    // each where one more of one side would do); what each side has is the samples cell.
    const double a = value_of(v, "samples_needed_a"), b = value_of(v, "samples_needed_b");
    if (std::isfinite(a) && std::isfinite(b))
      return fmt::format(
          "about {:.0f} samples per set would decide; cheapest: {:.0f} of the first set, {:.0f} "
          "of the second",
          v.samples_needed, a, b);
    return fmt::format("about {:.0f} samples per set would decide", v.samples_needed);
  }
  std::size_t end = v.reason.size();
  for (const char* clause_end : {": ", "; ", " (", " | "})
    end = std::min(end, v.reason.find(clause_end));
  return v.reason.substr(0, end);
}

TableRow table_row(const Verdict& v) {
  const std::string unit = effect_unit(v);
  const bool percent = unit == "relative";
  return {status_text(v),
          v.case_name,
          unit_words(unit),
          table_number(v.estimate, percent, true),
          allowed_text(v, percent),
          table_number(v.margin, percent),
          range_text(v),
          v.region.empty() ? "-" : v.region,
          samples_text(v),
          rule_text(v),
          short_reason(v)};
}

nlohmann::json to_json(const TableRow& r) {
  return {{"status", r.status},     {"case", r.case_name},     {"unit", r.unit},
          {"estimate", r.estimate}, {"allowed", r.allowed},    {"margin", r.margin},
          {"range", r.range},       {"region", r.region},      {"samples", r.samples},
          {"rule", r.rule},         {"short_reason", r.reason}};
}

TableRow table_row_from_json(const nlohmann::json& j) {
  const auto at = [&j](const char* key) { return j.at(key).get<std::string>(); };
  return {at("status"),  at("case"),   at("unit"),        at("estimate"),
          at("allowed"), at("margin"), at("range"),       at("region"),
          at("samples"), at("rule"),   at("short_reason")};
}

std::string format_table(const std::vector<Verdict>& verdicts) {
  std::ostringstream out;
  for (const CheckRows& c : by_check(verdicts)) {
    check_table(out, c);
    out << "\n";
  }
  out << fmt::format("{} verdicts, {}\n", verdicts.size(), outcome_counts(verdicts));
  return out.str();
}

}  // namespace jam::checks
