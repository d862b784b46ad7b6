// The words of verdicts on the terminal: each effect in one unit (relative effects in %, the
// same in the reasons as in the table), and the table `jam check` prints, one per check.
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

/// A table's number, in its table's unit (the header names it).
std::string table_number(double x, bool percent) {
  return std::isfinite(x) ? fmt::format("{:.3g}", percent ? 100 * x : x) : "-";
}

std::string status_text(const Verdict& v) {
  return v.expected_failure ? v.status + " (expected)" : v.status;
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

/// One check's table: heading, column header, rows (a line naming the unit before each group
/// when its effects come in more than one).
void check_table(std::ostringstream& out, const CheckRows& c) {
  std::size_t status_width = std::string("verdict").size(), case_width = 4;
  for (const auto& v : c.all) {
    status_width = std::max(status_width, status_text(v).size());
    case_width = std::max(case_width, v.case_name.size());
  }
  const bool one_unit = c.by_unit.size() == 1;
  out << fmt::format("{}: {} verdict{}, {}{}\n", c.check, c.all.size(),
                     c.all.size() == 1 ? "" : "s", outcome_counts(c.all),
                     one_unit ? "; effects in " + unit_words(c.by_unit.front().first) : "");
  // A pressure check that could place no region around jamming says so before its rows.
  const bool pooled = std::any_of(c.all.begin(), c.all.end(),
                                  [](const Verdict& v) { return v.region == "pooled"; });
  const bool regions = std::any_of(c.all.begin(), c.all.end(), [](const Verdict& v) {
    return v.region == "below" || v.region == "at" || v.region == "above" || v.region == "asked";
  });
  const bool whole = std::any_of(c.all.begin(), c.all.end(), [](const Verdict& v) {
    return v.region == "pooled" && v.values.count("whole_compression");
  });
  if (pooled && !regions) out << (whole ? kPooledWhole : kPooledOnly) << "\n";
  const std::string row = "  {:<{}}  {:<{}}  {:>10}  {:>14}  {:>8}  {}";
  out << trimmed(fmt::format(fmt::runtime(row), "verdict", status_width, "case", case_width,
                             "detectable", "excluded above", "margin", "reason"));
  for (const auto& [unit, rows] : c.by_unit) {
    if (!one_unit) out << fmt::format("  effects in {}:\n", unit_words(unit));
    const bool percent = unit == "relative";
    for (const Verdict* v : rows) {
      out << trimmed(fmt::format(fmt::runtime(row), status_text(*v), status_width, v->case_name,
                                 case_width, table_number(v->detectable, percent),
                                 table_number(v->excluded_above, percent),
                                 table_number(v->margin, percent), short_reason(*v)));
    }
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
    // The cheapest split per side, with what each side has now: "129 per set" read alone
    // sends a user to run 127 more of each where one more of one side would do.
    const auto at = [&v](const char* key) {
      const auto it = v.values.find(key);
      return it == v.values.end() ? NAN : it->second;
    };
    const double a = at("samples_needed_a"), b = at("samples_needed_b"), has_a = at("samples_a"),
                 has_b = at("samples_b");
    if (std::isfinite(a) && std::isfinite(b) && std::isfinite(has_a) && std::isfinite(has_b))
      return fmt::format(
          "about {:.0f} samples per set would decide; cheapest: {:.0f} of the first set (has "
          "{:.0f}), {:.0f} of the second (has {:.0f})",
          v.samples_needed, a, has_a, b, has_b);
    return fmt::format("about {:.0f} samples per set would decide", v.samples_needed);
  }
  std::size_t end = v.reason.size();
  for (const char* clause_end : {": ", "; ", " (", " | "})
    end = std::min(end, v.reason.find(clause_end));
  return v.reason.substr(0, end);
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
