#include "app/check_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "campaign/campaign_file.hpp"
#include "campaign/external_campaign.hpp"
#include "checks/check_registry.hpp"
#include "checks/run_checks.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/run/stop_signal.hpp"
#include "stats/stats_inputs.hpp"

namespace jam {
namespace {

/// Marks the verdicts named by the campaign's expected_failures ("check: part of the case").
void mark_expected_failures(std::vector<checks::Verdict>& verdicts,
                            const std::vector<std::string>& expected) {
  for (auto& v : verdicts) {
    for (const auto& e : expected) {
      const auto colon = e.find(": ");
      if (e.substr(0, colon) == v.check &&
          v.case_name.find(e.substr(colon + 2)) != std::string::npos) {
        v.expected_failure = true;
      }
    }
  }
}

/// What the campaign file says about judging it (DIR/campaign.toml, when there is one): its
/// name, margins, regions, expected failures, compared campaigns and question.
struct JudgingSettings {
  std::string name;
  std::map<std::string, double> margins;
  std::map<std::string, double> regions;  // [regions]
  std::vector<std::string> expected;
  std::vector<std::string> compare_with;  // other simulators' campaigns judged against this one
  CampaignQuestion question;              // [question]
};

JudgingSettings judging_settings(const std::string& directory) {
  const std::filesystem::path file = std::filesystem::path(directory) / "campaign.toml";
  JudgingSettings c{std::filesystem::absolute(directory).filename().string(), {}, {}, {}, {}, {}};
  if (std::filesystem::exists(file)) {
    const Campaign campaign = read_campaign(file.string());
    c = {campaign.name,         campaign.margins, campaign.regions, campaign.expected_failures,
         campaign.compare_with, campaign.question};
  }
  return c;
}

/// Refuses DIR/stats.h5 when it no longer describes DIR's runs (stats_inputs.hpp: runs
/// imported, finished or replaced since `jam stats`): verdicts on the averages of other runs
/// would be taken for verdicts on these.
void require_current_stats(const std::string& directory) {
  if (const std::string why = stats::stale_stats_reason(directory); !why.empty())
    throw std::runtime_error(fmt::format("{}: out of date: {}; run `jam stats {}`",
                                         (std::filesystem::path(directory) / "stats.h5").string(),
                                         why, directory));
}

/// Every campaign whose stats.h5 the checks will read: DIR (unless only lmp runs), the
/// --against directory and, for `all`, the campaigns of compare_with.
void require_current_inputs(const CheckArgs& a, const JudgingSettings& campaign) {
  const checks::CheckEntry* e = checks::find_check(a.name);
  if (!e || !std::holds_alternative<checks::LammpsCheck>(e->run))
    require_current_stats(a.directory);
  if (!a.against.empty()) require_current_stats(a.against);
  if (a.name == "all")
    for (const std::string& other : campaign.compare_with)
      if (std::filesystem::is_directory(other)) require_current_stats(other);
}

/// The table (checks/verdict_table.cpp), or one line of counts when another table follows
/// (the main job's report prints it with the headlines); then what the expected failures did.
void print_verdicts(const std::vector<checks::Verdict>& verdicts, bool table) {
  if (!table) {
    std::map<std::string, int> counts;
    for (const auto& v : verdicts) ++counts[v.status];
    fmt::print(
        "checks: {} verdicts: {} pass, {} fail, {} inconclusive (the table: the report's "
        "summary below)\n",
        verdicts.size(), counts["pass"], counts["fail"], counts["inconclusive"]);
    return;
  }
  fmt::print("{}", checks::format_table(verdicts));
  for (const auto& v : verdicts) {
    if (!v.expected_failure) continue;
    // An expected failure that did not fail says what it did instead.
    fmt::print("{} {}: {}\n",
               v.status == "fail"   ? std::string("expected failure:")
               : v.status == "pass" ? std::string("EXPECTED TO FAIL, PASSED:")
                                    : std::string("expected to fail, inconclusive:"),
               v.check, v.case_name);
  }
}

}  // namespace

void add_check_command(CLI::App& app, CheckArgs& a) {
  // The accepted names and the help text come from the registry (checks/check_registry.hpp).
  const std::vector<std::string> names = checks::command_names();
  std::string listed, not_in_all;
  for (const auto& name : names) listed += (listed.empty() ? "" : ", ") + name;
  for (const auto& e : checks::check_registry())
    if (!e.in_all) not_in_all += (not_in_all.empty() ? "" : ", ") + std::string(e.name);
  CLI::App* c = app.add_subcommand(
      "check", fmt::format("Statistical verdicts from DIR/stats.h5: {}. Each verdict is pass (the "
                           "data exclude effects beyond the margin), fail (the data exclude "
                           "effects at or below the margin: it surely exceeds it) or inconclusive",
                           listed));
  c->footer(
      "Exit status: 0 every verdict passes; 1 a verdict fails (expected failures named in the "
      "campaign file's expected_failures apart); 3 none fails but one is inconclusive; 2 the "
      "check could not run (usage error, missing or corrupt stats.h5).");
  c->option_defaults()->always_capture_default();
  // --json before --list: flags take effect in the order they are declared, and --list prints
  // as it is taken (before the required NAME and DIR are asked for).
  c->add_flag("--json", a.list_json, "--list: as JSON (what checks.json carries under checks)");
  c->add_flag_callback(
      "--list",
      [&a] {
        fmt::print("{}", a.list_json ? checks::registry_json() : checks::registry_table());
        throw CLI::Success();
      },
      "List the registered checks: kind, default margin and why, member of all, report figure");
  c->add_option("name", a.name,
                fmt::format("{} (all: all but {})", listed,
                            not_in_all.empty() ? std::string("none") : not_in_all))
      ->required()
      ->check(CLI::IsMember(names));
  c->add_option("directory", a.directory, "Campaign directory (after `jam stats`)")->required();
  // --alpha, --permutations, --phi-min, --phi-max, --margin, --reference-dir, --no-lmp: the
  // table `jam pipeline` shares (check_options.cpp).
  add_judging_options(c, a.judging);
  c->add_option("--set-a", a.set_a, "finite_size: first run set, e.g. n=1024,phi_init=0.6,rate=-4");
  c->add_option("--set-b", a.set_b, "finite_size: second run set");
  c->add_option("--against", a.against,
                "regression, chain, compare: the directory holding the stats.h5 to judge DIR "
                "against (regression: a baseline, e.g. a stored result in reference/results/; "
                "chain: the unchained control; compare: REF, the reference simulator's "
                "campaign)");
  c->add_option("--tolerance", a.regression.tolerance,
                "regression: largest relative difference of rerun samples (0: bitwise)");
  c->add_flag("--regenerate-reference", a.regenerate,
              "lammps: run lmp and rewrite the stored LAMMPS result in --reference-dir");
}

namespace {

/// The verdicts of one campaign of compare_with: verdicts[begin, end).
struct Comparison {
  std::string directory;
  std::size_t begin = 0, end = 0;
};

/// `all` of a campaign whose file names `compare_with`: each of those campaigns judged against
/// this one (`jam check compare OTHER --against THIS`), its verdicts named by both campaigns.
std::vector<Comparison> append_comparisons(std::vector<checks::Verdict>& verdicts,
                                           const JudgingSettings& campaign,
                                           const checks::CheckInputs& in) {
  std::vector<Comparison> out;
  for (const std::string& other : campaign.compare_with) {
    if (!std::filesystem::is_directory(other))
      throw std::runtime_error(fmt::format("compare_with: {}: no such campaign directory", other));
    checks::CheckInputs compare = in;
    compare.directory = other;
    compare.baseline_directory = in.directory;
    const std::string other_name = checks::read_stats(other).campaign;
    out.push_back({other, verdicts.size(), verdicts.size()});
    for (checks::Verdict v : checks::run_checks("compare", compare)) {
      if (const auto at = v.case_name.find("DIR vs REF"); at != std::string::npos)
        v.case_name.replace(at, 10, fmt::format("{} vs {}", other_name, campaign.name));
      else
        v.case_name = fmt::format("{} vs {}: {}", other_name, campaign.name, v.case_name);
      verdicts.push_back(std::move(v));
    }
    out.back().end = verdicts.size();
  }
  return out;
}

/// "PASS", "FAIL" or "INCONCLUSIVE", as the report's headline words them (expected failures
/// apart).
std::string outcome_word(const std::vector<checks::Verdict>& verdicts) {
  const int status = checks::exit_status(verdicts);
  return status == 1 ? "FAIL" : status == 3 ? "INCONCLUSIVE" : "PASS";
}

/// With compare_with: the headline of this campaign's own checks, then one line per compared
/// campaign. Another code's verdicts never turn this campaign's headline (a planted wrong code
/// once made the reference FAIL); they count in the exit status (checks::exit_status of all).
void print_headlines(const std::vector<checks::Verdict>& verdicts,
                     const std::vector<Comparison>& comparisons) {
  if (comparisons.empty()) return;
  const std::vector<checks::Verdict> own(
      verdicts.begin(), verdicts.begin() + static_cast<std::ptrdiff_t>(comparisons[0].begin));
  fmt::print("this campaign's own checks: {}: {}\n", outcome_word(own),
             checks::outcome_counts(own));
  for (const Comparison& c : comparisons) {
    const std::vector<checks::Verdict> theirs(
        verdicts.begin() + static_cast<std::ptrdiff_t>(c.begin),
        verdicts.begin() + static_cast<std::ptrdiff_t>(c.end));
    fmt::print("compare with {}: {}: {}\n", c.directory, outcome_word(theirs),
               checks::outcome_counts(theirs));
  }
}

/// Whether `all` judges the stored LAMMPS self-checks: when asked (--with-lammps; [question]
/// checks naming lammps run it by name), never for another simulator's runs (they test jam).
bool lammps_in_all(const CheckArgs& a, const checks::CheckInputs& in) {
  return a.judging.with_lammps && !in.runs_of_another_simulator;
}

/// The line `all` prints when it left the stored LAMMPS self-checks out.
void print_lammps_left_out() {
  fmt::print(
      "lammps: the LAMMPS self-checks were not run (they test jam against LAMMPS, not this "
      "campaign's data): `jam check lammps DIR`, `--with-lammps` or [question] checks naming "
      "lammps runs them\n");
}

}  // namespace

std::vector<std::string> checks_to_run(const std::vector<std::string>& wanted) {
  std::vector<std::string> out;
  for (const auto& e : checks::check_registry()) {
    if (!checks::runs_by_name(e) || e.name == "compare") continue;  // compare: compare_with's
    bool asked = false;
    for (const auto& w : wanted) {
      const checks::CheckEntry* x = checks::find_check(w);
      const auto* part = x ? std::get_if<checks::PartOf>(&x->run) : nullptr;
      asked = asked || w == e.name || (part && part->check == e.name);
    }
    if (asked) out.emplace_back(e.name);
  }
  return out;
}

bool question_wants(const std::vector<std::string>& wanted, const std::string& check) {
  if (wanted.empty()) return true;
  const checks::CheckEntry* e = checks::find_check(check);
  const auto* part = e ? std::get_if<checks::PartOf>(&e->run) : nullptr;
  for (const auto& w : wanted)
    if (w == check || (part && w == part->check)) return true;
  return false;
}

nlohmann::json check_record(const CheckArgs& a) {
  const JudgingSettings c = judging_settings(a.directory);
  return judging_record(a.judging,
                        check_options(a.judging, a.name, c.margins, c.regions, c.question),
                        a.name == "all" ? c.question : CampaignQuestion{});
}

int run_check_command(const CheckArgs& a) {
  validate_judging(a.judging);  // a bad option is one line, before anything is read
  // A campaign directory that is not there is a mistake in the command, not an empty result:
  // no check creates it (the lammps check writes its work files inside it).
  if (!std::filesystem::is_directory(a.directory)) {
    throw std::runtime_error(fmt::format("{}: no such campaign directory", a.directory));
  }
  // The three outputs, checked before any check runs (output_path.hpp): a FIFO or directory
  // there is refused now, not after the work.
  {
    const std::filesystem::path stem =
        std::filesystem::path(a.directory) / checks::verdict_file_stem(a.name);
    for (const char* ext : {".json", ".xml", ".h5"}) output_file_target(stem.string() + ext);
  }
  // Margins and expected failures: the campaign file's, then --margin.
  const JudgingSettings campaign = judging_settings(a.directory);
  require_current_inputs(a, campaign);
  checks::CheckOptions o =
      check_options(a.judging, a.name, campaign.margins, campaign.regions, campaign.question);
  if (!a.set_a.empty() || !a.set_b.empty()) {
    if (a.set_a.empty() || a.set_b.empty())
      throw std::runtime_error("--set-a and --set-b go together");
    o.set_a = checks::RunSetSelector::parse(a.set_a);
    o.set_b = checks::RunSetSelector::parse(a.set_b);
  }
  const auto started = std::chrono::steady_clock::now();
  checks::CheckInputs in;
  in.directory = a.directory;
  in.options = o;
  in.baseline_directory = a.against;
  in.regression = a.regression;
  in.lammps.work_directory = (std::filesystem::path(a.directory) / "lammps-check").string();
  in.lammps.reference_directory =
      (std::filesystem::path(a.judging.reference_dir) / "lammps").string();
  in.lammps.use_lmp = !a.judging.no_lmp;
  in.lammps.regenerate = a.regenerate;
  in.runs_of_another_simulator = is_external_campaign(a.directory);
  std::vector<checks::Verdict> verdicts;
  std::vector<Comparison> comparisons;
  bool lammps_judged = a.name != "all";
  if (a.name == "all" && !campaign.question.checks.empty()) {
    // The checks the question wants, each by name (a part through its check), never the rest.
    const std::vector<std::string>& wanted = campaign.question.checks;
    for (const std::string& name : checks_to_run(wanted)) {
      lammps_judged = lammps_judged || name == "lammps";
      for (auto& v : checks::run_checks(name, in))
        if (question_wants(wanted, v.check)) verdicts.push_back(std::move(v));
    }
    if (!lammps_judged && lammps_in_all(a, in)) {
      lammps_judged = true;
      for (auto& v : checks::run_checks("lammps", in)) verdicts.push_back(std::move(v));
    }
    if (question_wants(wanted, "compare")) comparisons = append_comparisons(verdicts, campaign, in);
  } else {
    verdicts = checks::run_checks(a.name, in);
    if (a.name == "all" && lammps_in_all(a, in)) {
      lammps_judged = true;
      for (auto& v : checks::run_checks("lammps", in)) verdicts.push_back(std::move(v));
    }
    if (a.name == "all") comparisons = append_comparisons(verdicts, campaign, in);
  }
  mark_expected_failures(verdicts, campaign.expected);
  print_verdicts(verdicts, a.table);
  print_headlines(verdicts, comparisons);
  if (!lammps_judged && !in.runs_of_another_simulator) print_lammps_left_out();
  // `all` writes checks.*, the files reports read; a single check writes checks-NAME.*, so
  // that it never replaces the full set.
  checks::write_verdict_files(
      a.directory, a.name, verdicts, campaign.name,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
      judging_record(a.judging, o, a.name == "all" ? campaign.question : CampaignQuestion{}));
  return checks::exit_status(verdicts);
}

}  // namespace jam
