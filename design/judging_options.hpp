#pragma once
// The options that decide how `jam check all` judges, declared once in one table
// (judging_options.cpp): `jam check` and `jam pipeline` both take them from it
// (app/check_options.hpp declares them to the command line). The table gives
// each option its flag, help, its key in the record and the rule its value must keep; from it
// follow the options of both commands, their validation (one line naming the option and the
// value, before any work) and the record written into checks.json ("options"), which is what
// tells `jam pipeline` that verdicts judged with other options are out of date.
//
// The options of single checks (--set-a/--set-b, --against, --tolerance,
// --regenerate-reference) stay with `jam check` (design/check_stage.hpp).
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "checks/checks.hpp"
#include "sim/io/install_paths.hpp"

namespace jam::design {

struct JudgingArgs {
  std::optional<double> alpha;  // absent: the campaign's [question] alpha, else kDefaultAlpha
  int permutations = 2000;
  // Absent: the campaign's [question] range (judged as the region "asked"), else the scaling
  // fit's window. Given where the campaign states a range: they replace it (still "asked");
  // where it states none: the range the pooled verdict judges.
  std::optional<double> phi_min, phi_max;
  std::optional<double> margin;  // absent: the campaign's [margins], else defaults
  std::optional<double> phi_j;   // absent: the campaign's [regions], the fit's, <phi_Ji>
  std::optional<double> region_near, region_far;  // absent: the campaign's, else the defaults
  std::string reference_dir = data_path("reference").string();
  bool no_lmp = false;
  // `all` (and the pipeline) also judge the stored LAMMPS self-checks (the lammps check),
  // which are otherwise left to `jam check lammps DIR` or [question] checks naming lammps.
  bool with_lammps = false;
};

/// The false-alarm rate of each check when neither --alpha nor [question] alpha gives one.
inline constexpr double kDefaultAlpha = 0.05;

struct JudgingOption {
  std::string flag;  // "--alpha"
  std::string key;   // its name in checks.json's "options"
  std::variant<double JudgingArgs::*, int JudgingArgs::*, std::optional<double> JudgingArgs::*,
               std::string JudgingArgs::*, bool JudgingArgs::*>
      field;
  std::string help;
  // The rule the value breaks, as "must be ..." words; "" when it keeps it (or is not given).
  std::function<std::string(const JudgingArgs&)> broken;
};

/// The table, in the order of `--help`.
const std::vector<JudgingOption>& judging_options();

/// Throws, naming the first option whose value breaks its rule and the value
/// ("--alpha 2: must be in (0, 1)").
void validate_judging(const JudgingArgs& args);

/// The statistical checks' options for check `name` (`all`: every check): the campaign's
/// margins, then --margin (for `name`, its parts, or every check under `all`); the regions
/// from --phi-j, --region-near, --region-far, else the campaign's [regions]; alpha from
/// --alpha, else [question] alpha; the range asked (the region "asked") from the question,
/// --phi-min/--phi-max replacing its ends; the rest as given. Validates first.
checks::CheckOptions check_options(const JudgingArgs& args, const std::string& name,
                                   const std::map<std::string, double>& campaign_margins,
                                   const std::map<std::string, double>& campaign_regions = {},
                                   const CampaignQuestion& question = {});

/// The question as judged (checks.json "question"): the range asked and where it was stated
/// (null when none: then "pooled" says what the pooled verdicts judge), the checks wanted
/// (null: all), each check's margin and alpha as used.
nlohmann::json question_record(const CampaignQuestion& question,
                               const checks::CheckOptions& options);

/// What the verdicts were judged with: every option of the table by its key (null when not
/// given; alpha as used), "margins", each registered check's margin as used, "regions" and
/// "question" (question_record).
nlohmann::json judging_record(const JudgingArgs& args, const checks::CheckOptions& options,
                              const CampaignQuestion& question = {});

}  // namespace jam::design
