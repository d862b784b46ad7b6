#pragma once
// A check's verdict, as CI acts on it and a physicist reads it: pass, fail or skipped (with
// why), the statistic and its threshold, and the smallest effect the data could have
// detected. Written as a table, as JSON and as JUnit XML.
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace jam::checks {

struct Verdict {
  std::string check;  // e.g. "finite_size", "sample_pairs", "phi_init"
  std::string
      case_name;  // what was compared, e.g. "n1024 vs n2048, phi_init 0.6, rate 1e-4, constant phi"
  std::string status;  // "pass", "fail" or "skipped"
  std::string reason;  // one line: why skipped, or what the numbers mean
  std::string statistic_name;
  double statistic = NAN;
  double threshold = NAN;
  double detectable = NAN;               // smallest effect the data could have detected
  double excluded_above = NAN;           // effects larger than this are excluded (where meaningful)
  std::map<std::string, double> values;  // further numbers a later stage reads (JSON "values")
  // Curves behind the verdict, for the report (checks.h5): e.g. "grid", "delta", "sigma".
  std::vector<std::pair<std::string, std::vector<double>>> curves;
};

/// A verdict that could not be reached, and why.
inline Verdict skipped(const std::string& check, const std::string& case_name,
                       const std::string& reason) {
  Verdict v;
  v.check = check;
  v.case_name = case_name;
  v.status = "skipped";
  v.reason = reason;
  return v;
}

std::string format_table(const std::vector<Verdict>& verdicts);
std::string to_json(const std::vector<Verdict>& verdicts);
std::string to_junit_xml(const std::vector<Verdict>& verdicts, const std::string& suite);

/// Writes the curves of every verdict to an HDF5 file (schema in reference/schema.md).
/// checks.h5: the verdicts' curves and values; root attributes `version` and `wall_time`
/// (seconds the checks took).
void write_curves(const std::string& path, const std::vector<Verdict>& verdicts, double wall_time);

/// 1 if any verdict failed, else 0.
int exit_status(const std::vector<Verdict>& verdicts);

}  // namespace jam::checks
