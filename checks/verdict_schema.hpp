#pragma once
// The rules of reference/schema/checks.toml (embedded at the build), applied to a parsed
// checks.json: the one definition of which files are verdict files, which python/jamio/
// checks.py applies too (tests/test_checks_schema.py feeds both the same corpus). The
// messages name the field and its value in the words jamio uses:
//   field 'status' is "maybe", not one of pass, fail, inconclusive
//   field 'values.n' is "x", not a number
//   field 'case' missing
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace jam::checks {

/// One field of a table of the schema.
struct SchemaField {
  std::string name;
  std::string type;  // string, number, integer, boolean, object, array
  bool required = false;
  bool null = false;                    // null accepted
  std::vector<nlohmann::json> allowed;  // the only values (empty: any of the type)
  std::string entries;                  // object: the type of every entry ("" unchecked)
  bool entries_null = false;            // ... or null
  std::string fields;                   // object: the schema table its fields follow
};

struct VerdictSchema {
  std::vector<int> versions;  // file versions read: 1 the bare array, 2 the object
  int current = 0;            // the version jam writes
  std::vector<SchemaField> object, verdict, table;
  const std::vector<SchemaField>& named(const std::string& table_name) const;
};

/// The schema, parsed once from the embedded reference/schema/checks.toml.
const VerdictSchema& verdict_schema();

/// Throws std::runtime_error with one line naming the first field of `j` (an object following
/// table `table_name`: "object", "verdict" or "table") that breaks its rule; `prefix` goes
/// before the field's name ("table." for a nested table's fields).
void check_fields(const nlohmann::json& j, const std::string& table_name,
                  const std::string& prefix = "");

/// The verdicts of a parsed checks.json of a version the schema reads, each checked
/// (throws: "verdict 3: field 'status' is ..."; a file neither an array nor an object with a
/// `verdicts` array: "neither an array of verdicts nor an object with a 'verdicts' array").
const nlohmann::json& checked_verdicts(const nlohmann::json& file);

}  // namespace jam::checks
