#pragma once
// A campaign: every run of a finite-size study, described by one TOML file
// (reference/campaigns/*.toml documents every key). Parsing is strict: unknown keys, wrong
// types, missing fields and impossible values are errors naming the file, the line and the key.
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/run/sim_config.hpp"

namespace jam {

struct CampaignError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Runs in one campaign file at most (samples x sizes x phi_init x rates): a plan keeps every
/// run in memory, about 1 kB each. Larger studies are several files (first_sample).
inline constexpr std::int64_t kMaxCampaignRuns = 100000;

/// The per-run defaults of a campaign: SimConfig's, except a fixed relaxation target (not
/// "auto", which depends on the rate) so that every rate of a sample shares one relaxed start,
/// cached in <output>/starts/, and no progress display.
SimConfig campaign_run_defaults();

/// [question]: what the campaign asks, stated in its file before its runs (docs/campaigns.md).
/// Only what [margins] and [regions] do not already say: the packing range judged (as the
/// region "asked" beside the pooled verdict, checks/regions.hpp), the checks wanted and the
/// false-alarm rate. `jam check`, `jam pipeline`, `jam campaign run --until-decided` and
/// `jam campaign plan` take it as their defaults; the command line's --phi-min, --phi-max and
/// --alpha override it. Keys absent: not stated.
struct CampaignQuestion {
  std::optional<double> phi_min, phi_max;  // both or neither
  std::vector<std::string> checks;         // empty: every check `jam check all` judges
  std::optional<double> alpha;
  bool states_range() const { return phi_min.has_value() && phi_max.has_value(); }
};

/// The names [question] checks accepts: the checks `jam check all` judges (parts too), compare
/// (the campaigns of compare_with judged against this one) and lammps (the LAMMPS
/// self-checks, which `all` judges only when asked).
std::vector<std::string> question_check_names();

struct Campaign {
  std::string name;
  std::vector<std::int64_t> sizes;
  std::vector<double> phi_init;
  std::vector<double> log10_rates;
  // Chained starts (sim/io/chain_start.hpp), one per log10_rates entry: 0 starts the rate from
  // the sample's relaxed random start; a packing phi'_init continues from the configuration the
  // next faster rate of the same sample passed through there. Empty: no chains.
  std::vector<double> chain_phi_init;
  // Runs redone from another campaign's starts (`jam campaign converge`): a campaign directory
  // whose plan holds every run of this one under the same name; each rate with a
  // chain_phi_init reads the start its namesake there read (from that campaign's parent run,
  // which `jam campaign run` rewrites first when it is gone), instead of chaining its own, so
  // the two differ only in how they integrate. Empty: none.
  std::string chain_starts_from;
  std::int64_t samples = 0;
  // Samples are numbered first_sample ... first_sample + samples - 1: a rerun of part of a
  // campaign (first_sample inside it) or new samples of it (first_sample past its end).
  std::int64_t first_sample = 0;
  std::uint64_t base_seed = 0;  // key "seed": each run's seed derives from it (run_plan.hpp)
  std::string output;           // campaign directory
  // Every run's parameters: the campaign keys of the parameter table (run_parameters.hpp) read
  // into it; n, phi_init, rate and seed are set per run by run_config().
  SimConfig run = campaign_run_defaults();
  // How `jam check` judges this campaign (not part of its identity: changing them never
  // touches a run). [margins]: a check's name -> its margin M (checks/checks.hpp).
  std::map<std::string, double> margins;
  // [regions]: where the regions around jamming lie when `jam check` is not told
  // (checks/regions.hpp): phi_j (fixing phi_J, e.g. for a registered follow-up whose regions
  // are stated before its runs), near and far (the offsets). Keys absent: the defaults.
  std::map<std::string, double> regions;
  CampaignQuestion question;  // [question]
  // Verdicts the campaign expects to fail, "check: text" with text a part of the case name
  // ("phi_init: phi_init 0.8 vs"): the main job names them as expected, not as a bare FAIL.
  std::vector<std::string> expected_failures;
  // Campaign directories of other simulators (external campaigns, docs/cross-simulator.md)
  // that `jam check all` and the pipeline compare with this one (`jam check compare OTHER
  // --against THIS`): this campaign is the reference.
  std::vector<std::string> compare_with;

  std::string source_path;  // the file it was read from
  std::string source_text;  // its text, stored with the results
};

/// Indices into log10_rates, fastest rate first.
std::vector<std::size_t> rates_fastest_first(const Campaign& c);

/// Reads and validates a campaign file.
Campaign read_campaign(const std::string& path);

/// Parses campaign text (path is used in messages and to resolve nothing else).
Campaign parse_campaign(const std::string& text, const std::string& path);

/// Keys whose change would mix incompatible runs in one directory, with their values as text.
std::vector<std::pair<std::string, std::string>> identity_keys(const Campaign& c);

}  // namespace jam
