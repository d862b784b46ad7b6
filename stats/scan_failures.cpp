#include "stats/scan_failures.hpp"

#include <fmt/format.h>

#include <regex>

namespace jam::stats {
namespace {

/// A reason with every number replaced by '#': the kind it belongs to.
std::string failure_kind_key(const std::string& reason) {
  static const std::regex number(R"([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)");
  return std::regex_replace(reason, number, "#");
}

/// The reason without the "fit: " that every fit's message starts with (the line says "fits").
std::string without_fit_prefix(const std::string& reason) {
  return reason.rfind("fit: ", 0) == 0 ? reason.substr(5) : reason;
}

}  // namespace

std::vector<ScanFailureKind> scan_failure_kinds(const FitScan& scan) {
  std::vector<ScanFailureKind> kinds;
  std::vector<std::string> keys;
  for (const auto& row : scan.rows) {
    if (row.result) continue;
    const std::string reason = without_fit_prefix(row.failure);
    const std::string key = failure_kind_key(reason);
    std::size_t k = 0;
    while (k < keys.size() && keys[k] != key) ++k;
    if (k == keys.size()) {
      keys.push_back(key);
      kinds.push_back({reason, 0, false});
    }
    ++kinds[k].rows;
    kinds[k].numbers_differ = kinds[k].numbers_differ || reason != kinds[k].reason;
  }
  return kinds;
}

std::string scan_failure_words(const FitScan& scan) {
  std::string out;
  for (const auto& kind : scan_failure_kinds(scan)) {
    out += fmt::format("{}{} row{}{}: {}", out.empty() ? "" : " | ", kind.rows,
                       kind.rows == 1 ? "" : "s", kind.numbers_differ ? ", e.g." : "", kind.reason);
  }
  return out;
}

}  // namespace jam::stats
