#pragma once
// reference/schema/stats.toml parsed (stats_schema_rules.cpp): its groups with their
// attributes and datasets, in the file's order. stats_schema.cpp applies them.
#include <optional>
#include <string>
#include <vector>

namespace jam::stats {

/// A value of an `allowed` list: a number or a string.
struct AllowedValue {
  bool is_string = false;
  double number = 0;
  std::string text;
};

struct AttributeRule {
  std::string name;
  std::string type;  // integer, float, string
  bool required = false;
  std::string required_unless;  // required unless the group has this attribute
  std::vector<AllowedValue> allowed;
  std::optional<double> min;
  bool finite = false;
};

struct DatasetRule {
  std::string name;
  std::string type;                // float
  std::vector<std::string> shape;  // named dimensions
  std::string unit;                // its attribute `units`, when it has one
  bool required = false;
  std::string required_unless;
  bool finite = false, whole = false;
  std::vector<AllowedValue> allowed;  // the only values other than NaN
};

struct GroupRule {
  std::vector<std::string> paths;  // "/", "ensembles/*", ...
  bool required = false;
  std::vector<std::string> one_of;  // at least one of these datasets
  std::vector<AttributeRule> attributes;
  std::vector<DatasetRule> datasets;
};

struct StatsSchema {
  std::vector<int> versions;
  int current = 0;
  std::vector<GroupRule> groups;
};

/// The schema, parsed once from the embedded reference/schema/stats.toml.
const StatsSchema& stats_schema();

}  // namespace jam::stats
