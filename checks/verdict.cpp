#include "checks/verdict.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <sstream>

namespace jam::checks {
namespace {

std::string number(double v) {
  return std::isfinite(v) ? fmt::format("{:.4g}", v) : "-";
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

std::string format_table(const std::vector<Verdict>& v) {
  std::ostringstream out;
  out << fmt::format("{:<8} {:<13} {:<58} {:>10} {:>10} {:>11} {:>10}\n", "verdict", "check",
                     "case", "statistic", "threshold", "detectable", "excluded>");
  for (const auto& x : v) {
    out << fmt::format("{:<8} {:<13} {:<58} {:>10} {:>10} {:>11} {:>10}\n", x.status, x.check,
                       x.case_name.size() > 58 ? x.case_name.substr(0, 55) + "..." : x.case_name,
                       number(x.statistic), number(x.threshold), number(x.detectable),
                       number(x.excluded_above));
    if (x.status != "pass" && !x.reason.empty()) out << "         " << x.reason << "\n";
  }
  int pass = 0, fail = 0, skipped = 0;
  for (const auto& x : v) (x.status == "pass" ? pass : x.status == "fail" ? fail : skipped)++;
  out << fmt::format("{} passed, {} failed, {} skipped\n", pass, fail, skipped);
  return out.str();
}

std::string to_json(const std::vector<Verdict>& v) {
  nlohmann::json j = nlohmann::json::array();
  auto num = [](double x) {
    return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
  };
  for (const auto& x : v) {
    j.push_back({{"check", x.check},
                 {"case", x.case_name},
                 {"status", x.status},
                 {"reason", x.reason},
                 {"statistic_name", x.statistic_name},
                 {"statistic", num(x.statistic)},
                 {"threshold", num(x.threshold)},
                 {"detectable_effect", num(x.detectable)},
                 {"excluded_above", num(x.excluded_above)},
                 {"values", x.values}});
  }
  return j.dump(2) + "\n";
}

std::string to_junit_xml(const std::vector<Verdict>& v, const std::string& suite) {
  int failures = 0, skipped = 0;
  for (const auto& x : v) {
    failures += x.status == "fail";
    skipped += x.status == "skipped";
  }
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << fmt::format("<testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
                     xml_escape(suite), v.size(), failures, skipped);
  for (const auto& x : v) {
    const std::string summary = fmt::format(
        "{} = {} (threshold {}), detectable {}, excluded above {}", x.statistic_name,
        number(x.statistic), number(x.threshold), number(x.detectable), number(x.excluded_above));
    out << fmt::format("  <testcase classname=\"jam.check.{}\" name=\"{}\">\n", xml_escape(x.check),
                       xml_escape(x.case_name));
    if (x.status == "fail") {
      out << fmt::format("    <failure message=\"{}\">{}</failure>\n", xml_escape(x.reason),
                         xml_escape(summary));
    } else if (x.status == "skipped") {
      out << fmt::format("    <skipped message=\"{}\"/>\n", xml_escape(x.reason));
    }
    out << fmt::format("    <system-out>{}</system-out>\n", xml_escape(summary));
    out << "  </testcase>\n";
  }
  out << "</testsuite>\n";
  return out.str();
}

int exit_status(const std::vector<Verdict>& v) {
  for (const auto& x : v)
    if (x.status == "fail") return 1;
  return 0;
}

}  // namespace jam::checks
