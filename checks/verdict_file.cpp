#include "checks/verdict_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "checks/check_registry.hpp"
#include "checks/verdict_schema.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/run/stop_signal.hpp"
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

nlohmann::json verdict_json(const Verdict& x) {
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{"check", x.check},
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
          // What every table shows of it (table_row): the report reads these cells rather
          // than computing its own.
          {"table", to_json(table_row(x))}};
}

std::string to_json(const std::vector<Verdict>& v, const std::string& campaign,
                    const nlohmann::json& options) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& x : v) j.push_back(verdict_json(x));
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

// ---- reading -------------------------------------------------------------------------------

namespace {

using nlohmann::json;

/// A number field (checked by the schema): NaN where absent or null.
double number(const json& v, const char* key) {
  return v.contains(key) && v[key].is_number() ? v[key].get<double>() : NAN;
}

std::string text(const json& v, const char* key) {
  return v.contains(key) ? v[key].get<std::string>() : std::string();
}

}  // namespace

Verdict verdict_from_json(const json& v) {
  Verdict x;
  x.check = text(v, "check");
  x.case_name = text(v, "case");
  x.status = text(v, "status");
  x.reason = text(v, "reason");
  x.statistic_name = text(v, "statistic_name");
  x.statistic = number(v, "statistic");
  x.threshold = number(v, "threshold");
  x.detectable = number(v, "detectable_effect");
  x.excluded_above = number(v, "excluded_above");
  x.excluded_below = number(v, "excluded_below");
  x.estimate = number(v, "estimate");
  x.region = text(v, "region");
  x.range_variable = text(v, "range_variable");
  x.margin = number(v, "margin");
  x.samples_needed = number(v, "samples_needed");
  x.expected_failure = v.value("expected_failure", false);
  x.unit = text(v, "unit");
  if (v.contains("values"))
    for (const auto& [key, value] : v["values"].items())
      x.values[key] = value.is_number() ? value.get<double>() : NAN;
  return x;
}

VerdictFile parse_verdict_file(const std::string& text_of_file, const std::string& where) {
  VerdictFile f;
  f.path = where;
  try {
    json j;
    try {
      j = json::parse(text_of_file);
    } catch (const json::parse_error& e) {
      throw std::runtime_error(fmt::format("not valid JSON (byte {})", e.byte));
    }
    const json& verdicts = checked_verdicts(j);
    if (j.is_array()) {
      f.schema_version = 1;
      f.registry = f.options = f.question = nullptr;
    } else {
      f.schema_version = j["schema_version"].get<int>();
      f.campaign = text(j, "campaign");
      f.code_version = text(j, "code_version");
      f.created = text(j, "created");
      f.registry = j.value("checks", json());
      f.options = j.value("options", json());
      f.question = j.value("question", json());
    }
    for (const json& v : verdicts) {
      f.verdicts.push_back(verdict_from_json(v));
      f.tables.push_back(v.contains("table") ? std::optional(table_row_from_json(v["table"]))
                                             : std::nullopt);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: {}", where, e.what()));
  }
  return f;
}

VerdictFile read_verdict_file(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw std::runtime_error(
        fmt::format("{}: no verdict file (judge the campaign: jam check)", path));
  check_input_file("verdict file", path);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  if (!in && !in.eof()) throw std::runtime_error(fmt::format("{}: cannot be read", path));
  return parse_verdict_file(all.str(), path);
}

// ---- writing -------------------------------------------------------------------------------

std::string verdict_file_stem(const std::string& check_name) {
  return check_name == "all" ? "checks" : "checks-" + check_name;
}

void write_verdict_files(const std::string& directory, const std::string& name,
                         const std::vector<Verdict>& verdicts, const std::string& campaign_name,
                         double seconds, const nlohmann::json& options) {
  // A stop asked for while judging (`jam pipeline`, `--until-decided`): nothing is written.
  throw_if_stop_requested("checks.json");
  const std::filesystem::path stem = std::filesystem::path(directory) / verdict_file_stem(name);
  for (const auto& [file, contents] :
       {std::pair{stem.string() + ".json", to_json(verdicts, campaign_name, options)},
        std::pair{stem.string() + ".xml", to_junit_xml(verdicts, "jam.check." + name)}}) {
    AtomicFile out(file);
    std::fputs(contents.c_str(), out.stream());
    out.commit();
  }
  write_curves(stem.string() + ".h5", verdicts, seconds);
  fmt::print("wrote {}.json, {}.xml and {}.h5\n", stem.string(), stem.string(), stem.string());
}

}  // namespace jam::checks
