#include "checks/verdict.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <ctime>
#include <nlohmann/json.hpp>
#include <sstream>

#include "checks/check_registry.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/version.hpp"

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

nlohmann::json verdict_array(const nlohmann::json& checks) {
  if (checks.is_array()) return checks;
  if (checks.is_object() && checks.contains("verdicts") && checks["verdicts"].is_array())
    return checks["verdicts"];
  throw std::runtime_error("checks.json: neither an array of verdicts nor an object with them");
}

std::string to_json(const std::vector<Verdict>& v, const std::string& campaign,
                    const nlohmann::json& options) {
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
                 {"excluded_below", num(x.excluded_below)},
                 {"estimate", num(x.estimate)},
                 {"region", x.region},
                 {"range_variable", x.range_variable},
                 {"margin", num(x.margin)},
                 {"unit", effect_unit(x)},
                 {"samples_needed", num(x.samples_needed)},
                 {"expected_failure", x.expected_failure},
                 {"values", x.values},
                 // What every table shows of it (table_row): the report reads these cells
                 // rather than computing its own.
                 {"table", to_json(table_row(x))}});
  }
  const std::time_t now = std::time(nullptr);
  char created[32];
  std::strftime(created, sizeof created, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  nlohmann::json file = {{"schema_version", kChecksSchemaVersion},
                         {"campaign", campaign},
                         {"code_version", std::string(kVersion)},
                         {"created", std::string(created)},
                         // The registry of the jam that judged: the report reads from
                         // it which figure shows which check (check_registry.hpp).
                         {"checks", nlohmann::json::parse(registry_json())},
                         {"verdicts", j}};
  // What the verdicts were judged with: `jam pipeline` judges again when it differs.
  if (!options.is_null()) file["options"] = options;
  // The question judged (range asked, checks, margins, alpha), at the top for its readers.
  if (options.is_object() && options.contains("question")) file["question"] = options["question"];
  return file.dump(2) + "\n";
}

std::string to_junit_xml(const std::vector<Verdict>& v, const std::string& suite) {
  // An expected failure is a finding the campaign already knows: JUnit sees it as skipped,
  // like an inconclusive verdict, with the reason.
  auto failure = [](const Verdict& x) { return x.status == "fail" && !x.expected_failure; };
  int failures = 0, skipped = 0;
  for (const auto& x : v) {
    failures += failure(x);
    skipped += !failure(x) && x.status != "pass";
  }
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << fmt::format("<testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
                     xml_escape(suite), v.size(), failures, skipped);
  for (const auto& x : v) {
    // The table's cells for this verdict, one per line, as the terminal and the report show
    // them (table_row), then the statistic.
    const TableRow r = table_row(x);
    const std::string summary = fmt::format(
        "effects in: {}\nestimate: {}\n|effect|: {}\nmargin: {}\nrange judged: {}\n"
        "region: {}\nsamples: {}\nreason: {}\ndecided by: {}\n{} = {} (threshold {}), "
        "detectable {}",
        r.unit, r.estimate, r.allowed, r.margin, r.range, r.region, r.samples, r.reason,
        r.rule.empty() ? "-" : r.rule, x.statistic_name, number(x.statistic), number(x.threshold),
        number(x.detectable));
    out << fmt::format("  <testcase classname=\"jam.check.{}\" name=\"{}\">\n", xml_escape(x.check),
                       xml_escape(x.case_name));
    if (failure(x)) {
      out << fmt::format("    <failure message=\"{}\">{}</failure>\n", xml_escape(x.reason),
                         xml_escape(summary));
    } else if (x.status != "pass") {
      const std::string why = x.expected_failure ? "expected failure: " + x.reason : x.reason;
      out << fmt::format("    <skipped message=\"{}\"/>\n", xml_escape(why));
    }
    out << fmt::format("    <system-out>{}</system-out>\n", xml_escape(summary));
    out << "  </testcase>\n";
  }
  out << "</testsuite>\n";
  return out.str();
}

void write_curves(const std::string& given, const std::vector<Verdict>& v, double wall_time) {
  const std::string path = output_file_target(given);
  const std::string temporary = AtomicFile::temporary_name(path);
  try {
    h5::File f = h5::File::create(temporary);
    f.write_attribute("version", std::string(kVersion));
    f.write_attribute("wall_time", wall_time);
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::string g = fmt::format("verdicts/{:03d}_{}", k, v[k].check);
      f.create_group(g);
      f.write_attribute("check", v[k].check, g);
      f.write_attribute("case", v[k].case_name, g);
      f.write_attribute("status", v[k].status, g);
      f.write_attribute("statistic", v[k].statistic, g);
      f.write_attribute("threshold", v[k].threshold, g);
      f.write_attribute("margin", v[k].margin, g);
      f.write_attribute("excluded_above", v[k].excluded_above, g);
      f.write_attribute("excluded_below", v[k].excluded_below, g);
      f.write_attribute("estimate", v[k].estimate, g);
      f.write_attribute("region", v[k].region, g);
      f.write_attribute("samples_needed", v[k].samples_needed, g);
      f.write_attribute("expected_failure", std::int64_t{v[k].expected_failure}, g);
      for (const auto& [name, value] : v[k].values) f.write_attribute(name, value, g);
      for (const auto& [name, values] : v[k].curves) f.write_dataset(g + "/" + name, values);
    }
    f.close();
    AtomicFile::publish(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

int exit_status(const std::vector<Verdict>& v) {
  bool inconclusive = false;
  for (const auto& x : v) {
    if (x.status == "fail" && !x.expected_failure) return 1;
    inconclusive = inconclusive || x.status == "inconclusive";
  }
  return inconclusive ? 3 : 0;
}

std::string outcome_counts(const std::vector<Verdict>& v) {
  int pass = 0, fail = 0, inconclusive = 0, expected = 0, expected_passed = 0;
  for (const auto& x : v) {
    if (x.status == "fail") (x.expected_failure ? expected : fail)++;
    if (x.status == "pass") ++pass;
    if (x.status == "pass" && x.expected_failure) ++expected_passed;
    if (x.status == "inconclusive") ++inconclusive;
  }
  std::string out = fmt::format("{} passed, {} failed, {} inconclusive", pass, fail, inconclusive);
  if (expected > 0) out += fmt::format(", {} failed as expected", expected);
  if (expected_passed > 0) out += fmt::format(" ({} expected to fail passed)", expected_passed);
  return out;
}

}  // namespace jam::checks
