// The parameter table (sim/run/run_parameters.hpp) and what derives from it: every option of
// `jam sim` and every campaign key reaches its SimConfig member, the spellings stay those of
// earlier versions, unknown keys and bad values are refused, the run file carries every
// attribute the table names and reference/schema.md, docs/cli.md and the default campaign file
// document them. The expected spellings and values are literals here, not read from the table.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "app/sim_command.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"
#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/run_parameters.hpp"

namespace fs = std::filesystem;
using jam::ParameterValue;
using jam::SimConfig;

namespace {

const fs::path kDir =
    fs::temp_directory_path() / ("jam-run-parameters-" + std::to_string(::getpid()));

// Each option of `jam sim`: a value other than its default, and what the member then holds.
struct Given {
  std::string text;  // "" for a flag
  ParameterValue value;
};
const std::map<std::string, Given> kOptions = {
    {"--dim", {"3", std::int64_t{3}}},
    {"--n", {"2048", std::int64_t{2048}}},
    {"--phi-init", {"0.5", 0.5}},
    {"--phi-stop", {"0.9", 0.9}},
    {"--phi-step", {"0.002", 0.002}},
    {"--rate", {"0.001", 0.001}},
    {"--dt", {"0.01", 0.01}},
    {"--dynamics", {"inertial", std::string("inertial")}},
    {"--integrator", {"verlet", std::string("verlet")}},
    {"--q", {"0.5", 0.5}},
    {"--seed", {"9223372036854775807", std::uint64_t{9223372036854775807ULL}}},
    {"--threads", {"2", std::int64_t{2}}},
    {"--skin", {"0.35", 0.35}},
    {"--diameter-ratio", {"1.5", 1.5}},
    {"--contact", {"hertzian", std::string("hertzian")}},
    {"--tolerance", {"1e-7", std::string("1e-7")}},
    {"--dense-output", {"0", false}},
    {"--transient-tolerance", {"off", std::string("off")}},
    {"--stiffest-mode", {"bound", std::string("bound")}},
    {"--error-norm", {"rms", std::string("rms")}},
    {"--relax", {"0", false}},
    {"--relax-energy", {"1e-9", std::string("1e-9")}},
    {"--relax-time-max", {"100", 100.0}},
    {"--rattlers", {"", true}},
    {"--stress", {"", true}},
    {"--read-lammps-data", {"in.data", std::string("in.data")}},
    {"--jamming-point", {"", true}},
    {"--jamming-search-from", {"0.8", 0.8}},
    {"--out", {"o.h5", std::string("o.h5")}},
    {"--write-lammps-data", {"w.data", std::string("w.data")}},
    {"--write-final-lammps-data", {"f.data", std::string("f.data")}},
    {"--quiet", {"", true}},
    {"--force", {"", true}},
    {"--checkpoint-interval", {"60", 60.0}},
    {"--write-start", {"s.h5", std::string("s.h5")}},
    {"--write-start-at", {"0.8", 0.8}},
    {"--read-start", {"r.h5", std::string("r.h5")}},
};

// Each per-run key of a campaign file (TOML text), and what every run's config then holds.
const std::map<std::string, Given> kCampaignKeys = {
    {"dim", {"3", std::int64_t{3}}},
    {"phi_stop", {"0.9", 0.9}},
    {"phi_step", {"0.002", 0.002}},
    {"dt", {"0.01", 0.01}},
    {"dynamics", {"\"inertial\"", std::string("inertial")}},
    {"integrator", {"\"verlet\"", std::string("verlet")}},
    {"q", {"0.5", 0.5}},
    {"skin", {"0.35", 0.35}},
    {"diameter_ratio", {"1.5", 1.5}},
    {"contact", {"\"hertzian\"", std::string("hertzian")}},
    {"tolerance", {"\"1e-7\"", std::string("1e-7")}},
    {"dense_output", {"false", false}},
    {"transient_tolerance", {"\"1e-5\"", std::string("1e-5")}},
    {"stiffest_mode", {"\"bound\"", std::string("bound")}},
    {"error_norm", {"\"rms\"", std::string("rms")}},
    {"relax", {"false", false}},
    {"relax_energy", {"\"1e-9\"", std::string("1e-9")}},
    {"relax_time_max", {"100.0", 100.0}},
    {"rattlers", {"true", true}},
    {"stress", {"true", true}},
    {"jamming_point", {"true", true}},
    {"checkpoint_interval", {"60.0", 60.0}},
};

const std::string kCampaignOnly = R"(name = "t"
sizes = [64]
phi_init = [0.7]
log10_rates = [-3]
samples = 1
seed = 5
output = "out"
)";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string campaign_rejection(const std::string& text) {
  try {
    jam::parse_campaign(text, "c.toml");
  } catch (const jam::CampaignError& e) {
    return e.what();
  }
  return "accepted";
}

std::string validation_error(const SimConfig& c) {
  try {
    jam::validate(c);
  } catch (const jam::ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

BOOST_AUTO_TEST_CASE(options_keep_their_spellings) {
  std::set<std::string> options, keys, expected_options, expected_keys;
  for (const auto& p : jam::run_parameters()) {
    options.insert(p.option());
    if (p.campaign != jam::CampaignKey::none) keys.insert(p.name);
  }
  for (const auto& [option, given] : kOptions) expected_options.insert(option);
  for (const auto& [key, given] : kCampaignKeys) expected_keys.insert(key);
  BOOST_TEST(options == expected_options, boost::test_tools::per_element());
  BOOST_TEST(keys == expected_keys, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(every_option_reaches_its_member) {
  CLI::App app;
  SimConfig c;
  jam::add_sim_command(app, c);
  std::vector<std::string> args = {"jam", "sim"};
  for (const auto& [option, given] : kOptions) {
    args.push_back(option);
    if (!given.text.empty()) args.push_back(given.text);
  }
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  app.parse(static_cast<int>(argv.size()), argv.data());
  const SimConfig defaults;
  for (const auto& p : jam::run_parameters()) {
    BOOST_TEST_CONTEXT(p.option()) {
      BOOST_TEST_REQUIRE(kOptions.count(p.option()) == 1u);
      BOOST_TEST((jam::field_value(defaults, p) != kOptions.at(p.option()).value));
      BOOST_TEST((jam::field_value(c, p) == kOptions.at(p.option()).value));
    }
  }
  // Spot checks straight on the members, independent of the table's member pointers.
  BOOST_TEST(c.compression_rate == 0.001);
  BOOST_TEST(c.read_lammps_data == "in.data");
  BOOST_TEST(c.jamming_search_from == 0.8);
  BOOST_TEST(c.contact == "hertzian");
  BOOST_TEST(c.seed == 9223372036854775807ULL);
}

BOOST_AUTO_TEST_CASE(every_campaign_key_reaches_each_run) {
  std::string text = kCampaignOnly;
  for (const auto& [key, given] : kCampaignKeys) text += key + " = " + given.text + "\n";
  const jam::Campaign c = jam::parse_campaign(text, "c.toml");
  const SimConfig run = jam::run_config(c, 64, 0.7, -3.0, 0);
  const SimConfig defaults = jam::campaign_run_defaults();
  for (const auto& [key, given] : kCampaignKeys) {
    BOOST_TEST_CONTEXT(key) {
      const jam::RunParameter* p = jam::find_run_parameter(key);
      BOOST_TEST_REQUIRE(p != nullptr);
      BOOST_TEST((jam::field_value(defaults, *p) != given.value));
      BOOST_TEST((jam::field_value(run, *p) == given.value));
    }
  }
  BOOST_TEST(run.contact == "hertzian");
  BOOST_TEST(run.dim == 3);
  BOOST_TEST(run.checkpoint_interval == 60.0);
  // Set per run, not by keys.
  BOOST_TEST(run.n == 64);
  BOOST_TEST(run.phi_init == 0.7);
  BOOST_TEST(run.compression_rate == 1e-3);
  BOOST_TEST(run.seed == jam::derive_seed(5, 64, 0.7, 0));
  BOOST_TEST(run.campaign == "t");
  BOOST_TEST(run.quiet);
  // A key left out keeps the campaign default; contact changes the identity of a directory.
  const jam::Campaign plain =
      jam::parse_campaign(kCampaignOnly + "dim = 2\nphi_stop = 0.86\n", "c.toml");
  BOOST_TEST(plain.run.contact == "harmonic");
  BOOST_TEST(plain.run.relax_energy == "1e-14");
  bool names_contact = false;
  for (const auto& [key, value] : jam::identity_keys(c)) names_contact |= key == "contact";
  BOOST_TEST(names_contact);
}

BOOST_AUTO_TEST_CASE(unknown_keys_and_bad_contacts_are_refused) {
  const std::string good = kCampaignOnly + "dim = 2\nphi_stop = 0.86\n";
  BOOST_TEST(campaign_rejection(good) == "accepted");
  BOOST_TEST(campaign_rejection(good + "colour = 3\n") == "c.toml:10: colour: unknown key");
  // Options of a single run that a campaign sets itself, or leaves at one thread, are not keys.
  for (const char* key : {"threads = 2", "rate = 0.001", "n = 64", "out = \"x\"", "force = true"}) {
    BOOST_TEST(campaign_rejection(good + key + "\n").find("unknown key") != std::string::npos, key);
  }
  BOOST_TEST(campaign_rejection(good + "contact = \"hertz\"\n") ==
             "c.toml:10: contact: hertz: must be harmonic or hertzian");
  BOOST_TEST(campaign_rejection(good + "contact = 1\n") == "c.toml:10: contact: must be a string");
  // "auto"-or-number keys take a bare number too; a word that is neither is refused.
  const auto bare = jam::plan_runs(jam::parse_campaign(good + "tolerance = 1e-5\n", "c.toml"));
  BOOST_TEST(bare.front().config.resolved_tolerance() == 1e-5);
  BOOST_TEST(campaign_rejection(good + "tolerance = \"tight\"\n") ==
             "c.toml:10: tolerance: tight: must be 'auto' or a number > 0");

  SimConfig c;
  c.out = "x.h5";
  c.contact = "hertz";
  BOOST_TEST(validation_error(c) == "--contact hertz: must be harmonic or hertzian");
  c.contact = "hertzian";
  BOOST_TEST(validation_error(c) == "accepted");

  fs::create_directories(kDir);
  const auto o = jam::test::run_jam_stderr(
      kDir / "err.txt", "sim --contact Hertzian --quiet --out " + (kDir / "x.h5").string());
  BOOST_TEST(o.status == 2);
  BOOST_TEST(o.output == "jam: error: --contact Hertzian: must be harmonic or hertzian\n");
  BOOST_TEST(!fs::exists(kDir / "x.h5"));
}

// The help of --contact names the laws of the list, as its allowed values do: a law added to
// the list (here a test-only one) is named with no edit of the help.
namespace {
struct TestOnlyContact : jam::HertzianContact {
  static constexpr const char* kName = "test-only";
};
}  // namespace

BOOST_AUTO_TEST_CASE(contact_help_comes_from_the_list) {
  using Longer = std::tuple<jam::HarmonicContact, jam::HertzianContact, TestOnlyContact>;
  BOOST_TEST(jam::contact_law_help<Longer>() ==
             "Contact law: harmonic, hertzian or test-only (default harmonic, the paper's)");
  const auto& table = jam::run_parameters();
  const auto row = std::find_if(table.begin(), table.end(),
                                [](const jam::RunParameter& p) { return p.name == "contact"; });
  BOOST_TEST_REQUIRE((row != table.end()));
  BOOST_TEST(row->help == "Contact law: harmonic or hertzian (default harmonic, the paper's)");
}

BOOST_AUTO_TEST_CASE(integrators_come_from_the_list) {
  SimConfig c;
  c.out = "x.h5";
  BOOST_TEST(c.resolved_integrator() == "chebyshev");
  c.dynamics = "inertial";
  BOOST_TEST(c.resolved_integrator() == "verlet");
  c.dt = 1e-4;
  c.integrator = "heun";
  BOOST_TEST(validation_error(c) == "--integrator heun: inertial dynamics takes verlet");
  c.dynamics = "overdamped";
  c.integrator = "verlet";
  BOOST_TEST(validation_error(c) ==
             "--integrator verlet: overdamped dynamics takes euler, heun or chebyshev");
  BOOST_TEST(jam::integrator_help() ==
             "euler, heun or chebyshev (overdamped; default chebyshev), verlet (inertial)");
  // The plan's cost counts force evaluations: Heun's step costs two of Euler's.
  const std::string base = kCampaignOnly + "dim = 2\nphi_stop = 0.86\n";
  const auto heun = jam::plan_runs(jam::parse_campaign(base + "integrator = \"heun\"\n", "c.toml"));
  const auto euler =
      jam::plan_runs(jam::parse_campaign(base + "integrator = \"euler\"\n", "c.toml"));
  BOOST_TEST(heun.front().estimated_particle_steps == 2 * euler.front().estimated_particle_steps);
}

BOOST_AUTO_TEST_CASE(run_file_carries_every_parameter_attribute) {
  fs::create_directories(kDir);
  SimConfig c;
  c.n = 16;
  c.phi_init = 0.6;
  c.phi_stop = 0.61;
  c.phi_step = 0.005;
  c.compression_rate = 1e-2;
  c.relax = false;
  c.contact = "hertzian";
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.out = (kDir / "run.h5").string();
  jam::run_compression(c);
  const jam::h5::File f = jam::h5::File::open_read(c.out);
  for (const auto& p : jam::run_parameters()) {
    if (!p.attribute.empty()) BOOST_TEST(f.has_attribute(p.attribute), p.attribute);
  }
  BOOST_TEST(f.read_attribute_string("contact") == "hertzian");
  BOOST_TEST(f.read_attribute_string("integrator") == "chebyshev");
  BOOST_TEST(f.read_attribute_double("tolerance") == 3e-3);  // auto at rate 1e-2
  BOOST_TEST(f.read_attribute_int("dense_output") == 1);
  BOOST_TEST(f.read_attribute_string("stiffest_mode") == "estimate");
  BOOST_TEST(f.read_attribute_string("error_norm") == "max");
  // Every Chebyshev step takes at least two force evaluations (s >= 2 stages).
  BOOST_TEST(f.read_attribute_int("force_evaluations") >= 2 * f.read_attribute_int("steps"));
  BOOST_TEST(f.read_attribute_int("steps") > 0);
  BOOST_TEST(f.read_attribute_double("compression_rate") == 1e-2);
  BOOST_TEST(f.read_attribute_double("q") == 0.0);  // overdamped
  BOOST_TEST(f.read_attribute_int("relax") == 0);
  BOOST_TEST(f.read_attribute_string("fingerprint").find(" contact=hertzian") != std::string::npos);
  fs::remove_all(kDir);
}

BOOST_AUTO_TEST_CASE(documents_name_every_parameter) {
  const std::string source = JAM_SOURCE_DIR;
  // reference/schema.md: the run file's table has a row per attribute, of the stored type.
  std::istringstream schema(slurp(source + "/reference/schema.md"));
  std::map<std::string, std::string> rows;  // attribute -> its table line
  bool in_run_file = false;
  for (std::string line; std::getline(schema, line);) {
    if (line.rfind("## ", 0) == 0) in_run_file = line.rfind("## Run file", 0) == 0;
    if (in_run_file && line.rfind("| `", 0) == 0) {
      rows[line.substr(3, line.find('`', 3) - 3)] = line;
    }
  }
  const SimConfig defaults;
  for (const auto& p : jam::run_parameters()) {
    if (p.attribute.empty()) continue;
    BOOST_TEST_CONTEXT(p.attribute) {
      BOOST_TEST_REQUIRE(rows.count(p.attribute) == 1u);
      const ParameterValue v = jam::stored_value(defaults, p);
      const char* type = std::holds_alternative<double>(v)        ? "| float64 |"
                         : std::holds_alternative<std::string>(v) ? "| string |"
                                                                  : "| int64 |";
      BOOST_TEST(rows[p.attribute].find(type) != std::string::npos, rows[p.attribute]);
      BOOST_TEST(rows[p.attribute].find(p.unit) != std::string::npos, rows[p.attribute]);
      for (const auto& choice : p.choices) {
        if (std::holds_alternative<std::string>(v)) {
          BOOST_TEST(rows[p.attribute].find("`" + choice + "`") != std::string::npos, choice);
        }
      }
    }
  }
  // docs/cli.md names every option of jam sim; the default campaign file every campaign key.
  const std::string cli = slurp(source + "/docs/cli.md");
  const std::string campaign = slurp(source + "/reference/campaigns/default.toml");
  for (const auto& p : jam::run_parameters()) {
    BOOST_TEST(cli.find("`" + p.option()) != std::string::npos, p.option());
    if (p.campaign != jam::CampaignKey::none) {
      const bool documented = campaign.find("\n" + p.name + " = ") != std::string::npos ||
                              campaign.find("\n# " + p.name + " = ") != std::string::npos;
      BOOST_TEST(documented, p.name);
    }
  }
}
