#pragma once
// The verdict files `jam check` writes into a campaign directory, read and written here only:
// checks.json (reference/schema/checks.toml, the schema both jam and jamio check against;
// reference/schema.md in words), checks.xml (JUnit) and checks.h5 (the curves). `jam check
// all` writes checks.*, a single check checks-NAME.*, so that it never replaces the full set.
// Every reader of a checks.json in jam goes through read_verdict_file: a file that breaks the
// schema is refused with one line naming the file, the verdict, the field and its value.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "checks/verdict.hpp"

namespace jam::checks {

/// The version of checks.json jam writes (reference/schema/checks.toml, [file] current).
constexpr int kChecksSchemaVersion = 2;

/// checks.json as read: every field of the schema. Schema 1 files (the bare array) have
/// only verdicts; the rest stays empty or null.
struct VerdictFile {
  std::string path;
  int schema_version = kChecksSchemaVersion;
  std::string campaign, code_version, created;
  nlohmann::json registry;  // "checks": the registry of the jam that wrote it; null if absent
  nlohmann::json options;   // what the verdicts were judged with; null if absent
  nlohmann::json question;  // the question they answer; null if absent
  std::vector<Verdict> verdicts;
  // Each verdict's `table` (the cells jam's tables showed), by the verdict's index; empty
  // where the file has none (files written before it).
  std::vector<std::optional<TableRow>> tables;
};

/// Reads and checks a checks.json (either schema). Throws std::runtime_error, one line:
/// "DIR/checks.json: verdict 3: field 'status' is \"maybe\", not one of \"pass\", ...".
VerdictFile read_verdict_file(const std::string& path);
/// The same from text; `where` names it in the messages.
VerdictFile parse_verdict_file(const std::string& text, const std::string& where);

/// One verdict as checks.json holds it (the schema's fields, "table" too): what every writer
/// of a verdict's record uses (checks.json, until-decided.json's decided verdicts).
nlohmann::json verdict_json(const Verdict& v);
/// A verdict from that form (its fields' types checked by the schema, or written by
/// verdict_json); absent or null numbers are NaN.
Verdict verdict_from_json(const nlohmann::json& v);

/// "checks" for `all`, else "checks-NAME": the stem of the three files.
std::string verdict_file_stem(const std::string& check_name);

/// checks.json's text: {"schema_version": 2, "campaign", "code_version", "created" (UTC),
/// "checks" (the registry, check_registry.hpp), "options" (what `jam check` judged with, when
/// given), "question" (options' question, when it has one), "verdicts": [...]}.
std::string to_json(const std::vector<Verdict>& verdicts, const std::string& campaign = "",
                    const nlohmann::json& options = nullptr);
std::string to_junit_xml(const std::vector<Verdict>& verdicts, const std::string& suite);
/// checks.h5: the verdicts' curves and values; root attributes `version` and `wall_time`
/// (seconds the checks took). Written under a temporary name and renamed.
void write_curves(const std::string& path, const std::vector<Verdict>& verdicts, double wall_time);

/// DIR/<stem>.json, .xml and .h5 (verdict_file_stem), each written whole under a temporary
/// name and renamed; nothing when a stop was asked for (throws Interrupted).
void write_verdict_files(const std::string& directory, const std::string& check_name,
                         const std::vector<Verdict>& verdicts, const std::string& campaign_name,
                         double seconds, const nlohmann::json& options = nullptr);

}  // namespace jam::checks
