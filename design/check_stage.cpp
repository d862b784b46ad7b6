#include "design/check_stage.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>

#include "campaign/campaign_file.hpp"
#include "campaign/external_campaign.hpp"
#include "checks/check_registry.hpp"
#include "checks/run_checks.hpp"
#include "checks/verdict_file.hpp"
#include "design/compare_with.hpp"
#include "sim/io/output_path.hpp"
#include "stats/stats_inputs.hpp"

namespace jam::design {
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
void require_current_inputs(const CheckRequest& a, const JudgingSettings& campaign) {
  const checks::CheckEntry* e = checks::find_check(a.name);
  if (!e || !std::holds_alternative<checks::LammpsCheck>(e->run))
    require_current_stats(a.directory);
  if (!a.against.empty()) require_current_stats(a.against);
  if (a.name == "all")
    for (const std::string& other : campaign.compare_with)
      if (std::filesystem::is_directory(other)) require_current_stats(other);
}

/// A campaign directory that is not there is a mistake in the command, not an empty result (no
/// check creates it: the lammps check writes its work files inside it); the three outputs are
/// checked before any check runs (output_path.hpp): a FIFO or directory there is refused now,
/// not after the work.
void require_directory_and_outputs(const CheckRequest& a) {
  if (!std::filesystem::is_directory(a.directory))
    throw std::runtime_error(fmt::format("{}: no such campaign directory", a.directory));
  const std::filesystem::path stem =
      std::filesystem::path(a.directory) / checks::verdict_file_stem(a.name);
  for (const char* ext : {".json", ".xml", ".h5"}) output_file_target(stem.string() + ext);
}

/// Everything the checks read: DIR, the options (the campaign's margins, then the command's),
/// --set-a/--set-b, --against, and the LAMMPS check's files.
checks::CheckInputs check_inputs(const CheckRequest& a, const checks::CheckOptions& options) {
  checks::CheckInputs in;
  in.directory = a.directory;
  in.options = options;
  if (!a.set_a.empty() || !a.set_b.empty()) {
    if (a.set_a.empty() || a.set_b.empty())
      throw std::runtime_error("--set-a and --set-b go together");
    in.options.set_a = checks::RunSetSelector::parse(a.set_a);
    in.options.set_b = checks::RunSetSelector::parse(a.set_b);
  }
  in.baseline_directory = a.against;
  in.regression = a.regression;
  in.lammps.work_directory = (std::filesystem::path(a.directory) / "lammps-check").string();
  in.lammps.reference_directory =
      (std::filesystem::path(a.judging.reference_dir) / "lammps").string();
  in.lammps.use_lmp = !a.judging.no_lmp;
  in.lammps.regenerate = a.regenerate;
  in.runs_of_another_simulator = is_external_campaign(a.directory);
  return in;
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

/// The verdicts of a run of the stage, the compared campaigns' among them, and whether the
/// stored LAMMPS self-checks were judged.
struct Judged {
  std::vector<checks::Verdict> verdicts;
  std::vector<Comparison> comparisons;
  bool lammps = false;
};

/// Whether `all` judges the stored LAMMPS self-checks: when asked (--with-lammps; [question]
/// checks naming lammps run it by name), never for another simulator's runs (they test jam).
void add_lammps_if_asked(const CheckRequest& a, const checks::CheckInputs& in, Judged& j) {
  if (j.lammps || !a.judging.with_lammps || in.runs_of_another_simulator) return;
  j.lammps = true;
  for (auto& v : checks::run_checks("lammps", in)) j.verdicts.push_back(std::move(v));
}

/// `all` of a campaign whose [question] names checks: those, each by name (a part through its
/// check), never the rest.
Judged judge_question(const CheckRequest& a, const JudgingSettings& campaign,
                      const checks::CheckInputs& in) {
  Judged j;
  const std::vector<std::string>& wanted = campaign.question.checks;
  for (const std::string& name : checks_to_run(wanted)) {
    j.lammps = j.lammps || name == "lammps";
    for (auto& v : checks::run_checks(name, in))
      if (question_wants(wanted, v.check)) j.verdicts.push_back(std::move(v));
  }
  add_lammps_if_asked(a, in, j);
  if (question_wants(wanted, "compare"))
    j.comparisons = append_comparisons(j.verdicts, campaign.compare_with, campaign.name, in);
  return j;
}

Judged judge(const CheckRequest& a, const JudgingSettings& campaign,
             const checks::CheckInputs& in) {
  if (a.name == "all" && !campaign.question.checks.empty()) return judge_question(a, campaign, in);
  Judged j;
  j.lammps = a.name != "all";
  j.verdicts = checks::run_checks(a.name, in);
  if (a.name == "all") {
    add_lammps_if_asked(a, in, j);
    j.comparisons = append_comparisons(j.verdicts, campaign.compare_with, campaign.name, in);
  }
  return j;
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

nlohmann::json check_record(const CheckRequest& a) {
  const JudgingSettings c = judging_settings(a.directory);
  return judging_record(a.judging,
                        check_options(a.judging, a.name, c.margins, c.regions, c.question),
                        a.name == "all" ? c.question : CampaignQuestion{});
}

int run_check_stage(const CheckRequest& a) {
  validate_judging(a.judging);  // a bad option is one line, before anything is read
  require_directory_and_outputs(a);
  // Margins and expected failures: the campaign file's, then --margin.
  const JudgingSettings campaign = judging_settings(a.directory);
  require_current_inputs(a, campaign);
  const checks::CheckOptions o =
      check_options(a.judging, a.name, campaign.margins, campaign.regions, campaign.question);
  const checks::CheckInputs in = check_inputs(a, o);
  const auto started = std::chrono::steady_clock::now();
  Judged j = judge(a, campaign, in);
  mark_expected_failures(j.verdicts, campaign.expected);
  print_verdicts(j.verdicts, a.table);
  print_headlines(j.verdicts, j.comparisons);
  if (!j.lammps && !in.runs_of_another_simulator)
    fmt::print(
        "lammps: the LAMMPS self-checks were not run (they test jam against LAMMPS, not this "
        "campaign's data): `jam check lammps DIR`, `--with-lammps` or [question] checks naming "
        "lammps runs them\n");
  // `all` writes checks.*, the files reports read; a single check writes checks-NAME.*, so
  // that it never replaces the full set.
  checks::write_verdict_files(
      a.directory, a.name, j.verdicts, campaign.name,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
      judging_record(a.judging, o, a.name == "all" ? campaign.question : CampaignQuestion{}));
  return checks::exit_status(j.verdicts);
}

}  // namespace jam::design
