#pragma once
// Every parameter of a run, declared once: one row per SimConfig member a user sets, naming
// its option of `jam sim`, its campaign key, its place in the fingerprints, its run-file
// attribute and its allowed values. The option parser (app/sim_command.cpp), the campaign
// parser and its unknown-key check (campaign/campaign_file.cpp), fingerprint() and
// relaxation_fingerprint() (sim_config.cpp) and the run-file writer (sim/io/run_file.cpp) all
// walk this table; tests/test_run_parameters.cpp checks that reference/schema.md documents
// every attribute it writes. A new parameter is a SimConfig member and a row here.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sim/run/sim_config.hpp"

namespace jam {

/// The SimConfig member a parameter lives in.
using ParameterField =
    std::variant<int SimConfig::*, std::int64_t SimConfig::*, double SimConfig::*,
                 bool SimConfig::*, std::string SimConfig::*, std::uint64_t SimConfig::*>;

/// A parameter's value; an int member is held as int64.
using ParameterValue = std::variant<std::int64_t, std::uint64_t, double, bool, std::string>;

/// Where a parameter enters the fingerprints (sim_config.hpp): as a word "key=value" always,
/// or as a word appended at the end only when it differs from its default, so that the
/// fingerprints of runs at the default are those of versions without the parameter.
enum class Identity { none, word, suffix_unless_default };

enum class CampaignKey { none, optional, required };

struct RunParameter {
  std::string name;  // campaign key; the option is "--" + name with '_' as '-'
  ParameterField field;
  std::string help;  // of the option
  CampaignKey campaign = CampaignKey::none;
  Identity identity = Identity::none;
  std::string fingerprint_key = {};  // its word in fingerprints when not `name`
  // Its place among the words of relaxation_fingerprint(); 0: not part of it. Suffixes follow
  // the words in table order whatever their number.
  int relaxation_position = 0;
  std::string attribute = {};  // run-file attribute; "": not written
  std::string unit = {};       // of the attribute, as reference/schema.md states it ("": none)
  std::vector<std::string> choices = {};  // allowed values (validate() rejects others)
  bool flag = false;                      // a bool given as a bare flag (--stress), not --relax 0
  bool inertial_only = false;             // stored as 0 unless the dynamics is inertial
  bool from_data_file = false;            // fingerprints store 0 when --read-lammps-data gives it
  // The value fingerprints and the run file store when it is not the member itself (a default
  // resolved, "auto" worked out).
  ParameterValue (*resolve)(const SimConfig&) = nullptr;
  // ... and in relaxation_fingerprint() when the relaxation uses another value (nullptr: the
  // same as resolve).
  ParameterValue (*resolve_relaxation)(const SimConfig&) = nullptr;
  // A suffix parameter leaves the fingerprints at this value (unset: at its value in a default
  // SimConfig), for a default that is resolved per run but must keep older runs' identity.
  std::optional<ParameterValue> unmarked = std::nullopt;

  std::string option() const;  // "--phi-init"
  std::string word() const;    // fingerprint key
  bool in_fingerprint() const { return identity != Identity::none; }
};

/// The table, in the order of the fingerprint's words.
const std::vector<RunParameter>& run_parameters();

/// The row named `name` (campaign key), or nullptr.
const RunParameter* find_run_parameter(std::string_view name);

/// The member's value.
ParameterValue field_value(const SimConfig& c, const RunParameter& p);

/// What fingerprints and the run file store: the resolved value, 0 for inertial_only
/// parameters of overdamped runs.
ParameterValue stored_value(const SimConfig& c, const RunParameter& p);

/// What relaxation_fingerprint() stores: stored_value() but for resolve_relaxation.
ParameterValue stored_relaxation_value(const SimConfig& c, const RunParameter& p);

/// The zero of a value's type (0, 0.0, false, "").
ParameterValue zero_like(const ParameterValue& v);

/// A value as fingerprints write it: doubles with 17 significant digits, bools true/false.
std::string fingerprint_text(const ParameterValue& v);

/// A value as one-line errors show it: doubles as %g.
std::string message_text(const ParameterValue& v);

}  // namespace jam
