// The check registry (checks/check_registry.hpp) is what names the checks: its names are
// unique and complete; every name it registers is accepted by `jam check` (the ones that run
// by name) and as a campaign file's [margins] key, and a name it does not register is refused
// by both in one line naming it; `all` runs exactly the members of `all`.
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>

#include "campaign/campaign_file.hpp"
#include "campaign/check_names.hpp"
#include "checks/check_registry.hpp"
#include "checks/run_checks.hpp"
#include "checks/verdict_ensembles.hpp"
#include "process.hpp"
#include "synthetic_runs.hpp"

namespace fs = std::filesystem;
using namespace jam;
using namespace jam::checks;

namespace {

const std::string kCampaign = R"(name = "t"
dim = 2
sizes = [64, 128]
phi_init = [0.7, 0.8]
log10_rates = [-3]
samples = 3
phi_stop = 0.86
seed = 5
output = "out"
)";

/// A fresh empty directory under the system's temporary directory.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("jam-test-check-registry-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The names of the entries that are members of `all`: those that run by name, and also the
/// parts when `with_parts`.
std::set<std::string> members_of_all(bool with_parts) {
  std::set<std::string> out;
  for (const auto& e : check_registry())
    if (e.in_all && (with_parts || runs_by_name(e))) out.emplace(e.name);
  return out;
}

std::set<std::string> names_in(const std::vector<Verdict>& verdicts) {
  std::set<std::string> out;
  for (const auto& v : verdicts) out.insert(v.check);
  return out;
}

/// stderr of `jam <args>` with its exit status.
test::Outcome jam_stderr(const fs::path& dir, const std::string& args) {
  return test::run_jam_stderr(dir / "stderr.txt", args);
}

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

BOOST_AUTO_TEST_CASE(names_are_unique_and_entries_complete) {
  std::set<std::string> names;
  for (const auto& e : check_registry()) {
    BOOST_TEST(names.insert(std::string(e.name)).second, "registered twice: " << e.name);
    BOOST_TEST(e.name != "all");  // the command's word for every member
    BOOST_TEST(e.default_margin > 0.0, e.name);
    BOOST_TEST(default_margin(std::string(e.name)) == e.default_margin, e.name);
    BOOST_TEST(!e.margin_reason.empty(), e.name);
    BOOST_TEST(!e.figure.empty(), e.name);
    BOOST_TEST(find_check(e.name) == &e, e.name);
    // Every check declares which ensembles its verdicts concern (verdict_ensembles.hpp), so
    // that --until-decided and `campaign plan` serve it: a check that declares nothing is
    // refused here, never skipped at run time.
    BOOST_TEST_REQUIRE(e.samples != nullptr, e.name << " declares no ensembles");
    BOOST_TEST(e.samples->ensembles != nullptr, e.name);
    BOOST_TEST(e.samples->planned != nullptr, e.name);
    BOOST_TEST(!e.samples->identity.empty(), e.name);
    // A part's verdicts are written by a check that runs by name, and only in `all` with it.
    if (const auto* part = std::get_if<PartOf>(&e.run)) {
      const CheckEntry* parent = find_check(part->check);
      BOOST_TEST_REQUIRE(parent != nullptr, e.name << " part of an unregistered check");
      BOOST_TEST(runs_by_name(*parent), e.name);
      BOOST_TEST(parent->in_all == e.in_all, e.name);
    }
  }
  BOOST_TEST(names == check_names(), "the header's names and the table's entries differ");
  // The names campaign/ checks campaign files against, generated from the table at configure
  // time (campaign/check_names.hpp.in): every entry, in order, with its membership of `all`.
  BOOST_TEST_REQUIRE(std::size(jam::kRegisteredCheckNames) == check_registry().size());
  for (std::size_t k = 0; k < check_registry().size(); ++k) {
    BOOST_TEST(jam::kRegisteredCheckNames[k].name == check_registry()[k].name);
    BOOST_TEST(jam::kRegisteredCheckNames[k].in_all == check_registry()[k].in_all);
    const CheckRun& run = check_registry()[k].run;
    const std::string_view kind = std::holds_alternative<StatsCheck>(run)      ? "stats"
                                  : std::holds_alternative<BaselineCheck>(run) ? "baseline"
                                  : std::holds_alternative<LammpsCheck>(run)   ? "lammps"
                                                                               : "part";
    BOOST_TEST(jam::kRegisteredCheckNames[k].kind == kind, check_registry()[k].name);
  }
  BOOST_TEST(find_check("no_such_check") == nullptr);
  BOOST_CHECK_THROW(default_margin("no_such_check"), std::invalid_argument);
  // The listing that checks.json carries names every entry once, with its figure.
  const auto json = nlohmann::json::parse(registry_json());
  BOOST_TEST_REQUIRE(json.size() == check_registry().size());
  for (std::size_t k = 0; k < json.size(); ++k) {
    BOOST_TEST(json[k]["name"] == std::string(check_registry()[k].name));
    BOOST_TEST(json[k]["figure"] == std::string(check_registry()[k].figure));
  }
}

BOOST_AUTO_TEST_CASE(jam_check_accepts_every_registered_name_and_refuses_others) {
  const fs::path dir = scratch("command");
  const std::string missing = (dir / "no-campaign").string();
  std::set<std::string> accepted;
  for (const auto& name : command_names()) accepted.insert(name);
  BOOST_TEST(accepted.count("all") == 1u);
  for (const auto& e : check_registry()) {
    const std::string name(e.name);
    BOOST_TEST(accepted.count(name) == (runs_by_name(e) ? 1u : 0u), name);
    // Past the name: the command goes on to the directory, which is not there.
    const auto out = jam_stderr(dir, "check " + name + " " + missing);
    BOOST_TEST(out.status == 2, name << ": " << out.output);
    BOOST_TEST(lines(out.output) == 1u, out.output);
    if (runs_by_name(e)) {
      BOOST_TEST(out.output.find("no such campaign directory") != std::string::npos,
                 name << ": " << out.output);
    } else {
      BOOST_TEST(out.output.find("name: " + name + " not in") != std::string::npos, out.output);
    }
  }
  const auto all = jam_stderr(dir, "check all " + missing);
  BOOST_TEST(all.output.find("no such campaign directory") != std::string::npos, all.output);
  // The other commands that take a campaign directory say the same, not "cannot read campaign
  // file" (a mistyped path is not a damaged campaign).
  for (const std::string command : {"stats ", "campaign status ", "report "}) {
    const auto o = jam_stderr(dir, command + missing);
    BOOST_TEST(o.status == 2, command << o.output);
    BOOST_TEST(o.output.find("no such campaign directory") != std::string::npos,
               command << o.output);
  }
  const auto refused = jam_stderr(dir, "check no_such_check " + missing);
  BOOST_TEST(refused.status == 2);
  BOOST_TEST(lines(refused.output) == 1u, refused.output);
  BOOST_TEST(refused.output.find("no_such_check") != std::string::npos, refused.output);
  // `jam check --list` lists the registry without NAME or DIR.
  const auto list = test::run_jam_logged(dir / "list.txt", "check --list --json");
  BOOST_TEST(list.status == 0, list.output);
  BOOST_TEST(nlohmann::json::parse(list.output) == nlohmann::json::parse(registry_json()));
}

BOOST_AUTO_TEST_CASE(campaign_margins_accept_every_registered_name_and_refuse_others) {
  for (const auto& e : check_registry()) {
    const std::string name(e.name);
    const Campaign c = parse_campaign(kCampaign + "[margins]\n" + name + " = 0.25\n", "c.toml");
    BOOST_TEST(c.margins.at(name) == 0.25, name);
  }
  try {
    parse_campaign(kCampaign + "[margins]\nno_such_check = 0.25\n", "c.toml");
    BOOST_FAIL("an unregistered [margins] key was accepted");
  } catch (const CampaignError& e) {
    BOOST_TEST(std::string(e.what()) == "c.toml:10: margins: no_such_check: unknown check");
  }
  // From the command line: `jam check` reads the campaign directory's campaign.toml first.
  const fs::path dir = scratch("margins");
  std::ofstream(dir / "campaign.toml") << kCampaign << "[margins]\nno_such_check = 0.25\n";
  const auto out = jam_stderr(dir, "check all " + dir.string());
  BOOST_TEST(out.status == 2);
  BOOST_TEST(lines(out.output) == 1u, out.output);
  BOOST_TEST(out.output.find("margins: no_such_check: unknown check") != std::string::npos,
             out.output);
}

// [question] checks names what `jam check all` and --until-decided judge: every member of
// `all`, and every check of the campaign's own data (or LAMMPS) that `all` leaves out unless
// asked, with no list of names kept beside the registry.
BOOST_AUTO_TEST_CASE(campaign_question_accepts_every_check_of_its_own_data) {
  for (const auto& e : check_registry()) {
    const std::string name(e.name);
    if (!e.in_all && !std::holds_alternative<StatsCheck>(e.run) &&
        !std::holds_alternative<LammpsCheck>(e.run))
      continue;
    const Campaign c =
        parse_campaign(kCampaign + "[question]\nchecks = [\"" + name + "\"]\n", "c.toml");
    BOOST_TEST(c.question.checks == std::vector<std::string>{name}, name);
  }
}

BOOST_AUTO_TEST_CASE(all_runs_exactly_the_members_of_all) {
  // Statistical checks on synthetic sets with jamming points, so that phi_init writes its
  // part's (jamming_point) verdicts too.
  std::mt19937_64 rng(5);
  StatsData d;
  for (double phi_init : {0.6, 0.8}) {
    for (std::int64_t n : {1024, 2048}) {
      auto e = testing::ensemble(n, phi_init, -4.0, testing::runs(6, 0.0, rng));
      e.jamming_points.assign(6, 0.84);
      for (auto& p : e.jamming_points) p += 0.001 * std::normal_distribution<double>()(rng);
      d.ensembles.push_back(e);
    }
  }
  CheckOptions o;
  o.permutations = 100;
  std::set<std::string> statistical;
  for (const auto& e : check_registry()) {
    const auto* part = std::get_if<PartOf>(&e.run);
    const CheckEntry* runner = part ? find_check(part->check) : &e;
    if (e.in_all && std::holds_alternative<StatsCheck>(runner->run)) statistical.emplace(e.name);
  }
  BOOST_TEST(names_in(run_check("all", d, o)) == statistical);
  for (const auto& name : statistical)
    if (std::holds_alternative<StatsCheck>(find_check(name)->run))
      BOOST_TEST(!run_check(name, d, o).empty(), name);
  BOOST_CHECK_THROW(run_check("lammps", d, o), std::invalid_argument);
  BOOST_CHECK_THROW(run_check("no_such_check", d, o), std::invalid_argument);

  // Every kind, on a stored stats.h5 (with jamming points at two phi_init, so phi_init writes
  // its part's verdicts too) and the stored LAMMPS result: each member of `all` writes
  // verdicts, nothing else does.
  const fs::path dir = scratch("all");
  fs::copy_file(fs::path(JAM_SOURCE_DIR) / "reference/results/reduced-2d/stats.h5",
                dir / "stats.h5");
  CheckInputs in;
  in.directory = dir.string();
  in.options = o;
  in.lammps.work_directory = (dir / "lammps-check").string();
  in.lammps.reference_directory = (fs::path(JAM_SOURCE_DIR) / "reference/lammps").string();
  in.lammps.use_lmp = false;
  const auto names = names_in(run_checks("all", in));
  BOOST_TEST(names == members_of_all(true));
  BOOST_CHECK_THROW(run_checks("jamming_point", in), std::invalid_argument);
  // A baseline check needs its baseline: the error names the check and the option.
  for (const auto& e : check_registry()) {
    if (!std::holds_alternative<BaselineCheck>(e.run)) continue;
    try {
      run_checks(std::string(e.name), in);
      BOOST_FAIL(e.name << " ran without --against");
    } catch (const std::runtime_error& x) {
      BOOST_TEST(std::string(x.what()).find("--against") != std::string::npos, x.what());
    }
  }
  fs::remove_all(dir);
}

// Each registry line declares which ensembles its check's verdicts concern
// (checks/verdict_ensembles.hpp): --until-decided adds samples to them and `campaign plan`
// plans the comparisons the declaration names, with no check named anywhere else. The
// declarations decode the values their checks write.
BOOST_AUTO_TEST_CASE(each_check_declares_the_ensembles_its_verdicts_concern) {
  auto ensembles = [](const char* check, const checks::Values& values) {
    return find_check(check)->samples->ensembles(values);
  };
  using E = EnsembleId;
  const auto sizes = ensembles(
      "finite_size", {{"n_a", 256}, {"n_b", 1024}, {"phi_init", 0.4}, {"log10_rate", -4}});
  BOOST_TEST((sizes == std::vector<E>{{256, 0.4, -4}, {1024, 0.4, -4}}));
  const auto starts = ensembles(
      "phi_init", {{"n", 256}, {"phi_init", 0.6}, {"lowest_phi_init", 0.4}, {"log10_rate", -5}});
  BOOST_TEST((starts == std::vector<E>{{256, 0.6, -5}, {256, 0.4, -5}}));
  const auto rates = ensembles(
      "zeta", {{"n", 64}, {"phi_init", 0.4}, {"log10_rate_slow", -5}, {"log10_rate_faster", -4.5}});
  BOOST_TEST((rates == std::vector<E>{{64, 0.4, -5}, {64, 0.4, -4.5}}));
  // A fit's verdict: no pair of ensembles whose samples decide it, said by its declaration.
  BOOST_TEST(ensembles("fit_parameters", {{"n_a", 256}, {"n_b", 1024}}).empty());
  // The planner's comparisons: the smallest size against the largest at constant phi and Z,
  // every phi_init above the lowest against it; the others plan none.
  const Campaign c = parse_campaign(kCampaign, "c.toml");
  std::size_t planned = 0;
  for (const auto& e : check_registry()) {
    for (const auto& values : e.samples->planned(c)) {
      ++planned;
      BOOST_TEST(e.samples->ensembles(values).size() == 2u, e.name);
    }
  }
  const std::size_t phi_inits = c.phi_init.size(), rates_n = c.log10_rates.size();
  const std::size_t expected = (c.sizes.size() >= 2 ? phi_inits * rates_n * 2 : 0) +
                               (phi_inits >= 2 ? c.sizes.size() * rates_n * (phi_inits - 1) : 0);
  BOOST_TEST(planned == expected);
}

// A verdict's identity across the looks of --until-decided (verdict_identity) holds everything
// its check's declaration names: two fit_parameters verdicts of a campaign with several
// phi_init, the same sizes compared at two starts, or in two regions, are two verdicts (with
// the sizes alone, a verdict decided at one start stood for the other's).
BOOST_AUTO_TEST_CASE(fit_verdicts_are_identified_by_their_starts_and_region) {
  auto family = [](std::int64_t n, double phi_init) {
    FamilyParameters f;
    f.n = n;
    f.phi_init = phi_init;
    f.beta = 2.8, f.beta_err = 0.03;
    f.y = 1.05, f.y_err = 0.01;
    f.phi_j = 0.8415, f.phi_j_err = 0.0001;
    f.samples = 10;
    return f;
  };
  StatsData d;
  d.families = {family(256, 0.4), family(1024, 0.4), family(256, 0.6), family(1024, 0.6)};
  const std::vector<Verdict> verdicts = fit_parameters_check(d, CheckOptions{});
  // n256 vs n1024 at each start, and each size's start 0.6 against 0.4: two verdicts each.
  BOOST_TEST_REQUIRE(verdicts.size() == 8u);
  std::set<std::string> identities;
  for (const auto& v : verdicts) identities.insert(verdict_identity(v));
  BOOST_TEST(identities.size() == verdicts.size());
  BOOST_TEST(identities.count("fit_parameters n_a=256 n_b=1024 phi_init_a=0.4 phi_init_b=0.4"));
  // The same comparison in two regions.
  Verdict below = verdicts[0], above = verdicts[0];
  below.region = "below";
  above.region = "above";
  BOOST_TEST(verdict_identity(below) != verdict_identity(above));
  // A pooled verdict names no region (states written before regions name none).
  Verdict pooled = verdicts[0];
  pooled.region = "pooled";
  BOOST_TEST(verdict_identity(pooled) == verdict_identity(verdicts[0]));
}
