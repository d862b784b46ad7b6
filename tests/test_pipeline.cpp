// `jam pipeline FILE`, the main job, end to end through the executable on a small campaign:
// it runs, averages, judges and draws, printing the verdicts once (the report's summary; the
// check stage gives one line of counts); run again it redoes nothing. The check options are
// `jam check`'s: checks.json records those it was judged with, other options judge again (and
// the same ones do not), and a bad value is one line naming it, before any run. `jam check` on
// the same directory prints one table per check with its cases whole. Statistics are averaged
// again when the runs' digest changes, not when they are merely touched.
#include <boost/test/unit_test.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "process.hpp"
#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("pipeline");

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

nlohmann::json checks_json() {
  return nlohmann::json::parse(jam::test::slurp(kDir / "p" / "checks.json"));
}

std::string campaign_text(const fs::path& output) {
  return "name = \"p\"\ndim = 2\nsizes = [64, 128]\nphi_init = [0.70]\n"
         "log10_rates = [-2.5, -3.0]\nsamples = 3\nphi_stop = 0.86\n"
         "phi_step = 0.002\ndt = 0.02\nseed = 5\noutput = \"" +
         output.string() + "\"\n";
}

const std::string& pipeline_args() {
  static const std::string args = "pipeline " + (kDir / "p.toml").string() +
                                  " --jobs 2 --no-lmp --report " + (kDir / "report").string();
  return args;
}

}  // namespace

BOOST_AUTO_TEST_CASE(runs_judges_draws_and_then_redoes_nothing) {
  fs::create_directories(kDir);
  std::ofstream(kDir / "p.toml") << campaign_text(kDir / "p");
  const auto first = jam::test::run_jam_logged(kDir / "first.txt", pipeline_args());
  // 0: done, whatever the verdicts say (they are in the report's summary).
  BOOST_TEST(first.status == 0, first.output);
  BOOST_TEST(fs::exists(kDir / "report" / "index.html"));
  BOOST_TEST(first.output.find("checks: ") != std::string::npos, first.output);
  // The verdicts printed once: the longest case name (whole) in one line of the output.
  std::string longest;
  const nlohmann::json judged = checks_json();
  for (const auto& v : judged["verdicts"])
    if (v["case"].get<std::string>().size() > longest.size()) longest = v["case"];
  BOOST_TEST(count(first.output, longest) == 1, longest << "\n" << first.output);
  // What the verdicts were judged with.
  const auto options = checks_json()["options"];
  BOOST_TEST(options["alpha"] == 0.05, options.dump());
  BOOST_TEST(options["no_lmp"] == true, options.dump());
  BOOST_TEST(options["margins"]["finite_size"] == 0.1, options.dump());
  // The LAMMPS self-checks test jam, not the campaign: left out unless asked, in one line.
  BOOST_TEST(options["with_lammps"] == false, options.dump());
  for (const auto& v : judged["verdicts"]) BOOST_TEST(v["check"] != "lammps", v.dump());
  BOOST_TEST(count(first.output, "lammps: the LAMMPS self-checks were not run") == 1, first.output);
  const auto again = jam::test::run_jam_logged(kDir / "again.txt", pipeline_args());
  BOOST_TEST(again.status == 0, again.output);
  for (const char* stage : {"stats: ", "checks: ", "report: "})
    BOOST_TEST(again.output.find(std::string(stage)) != std::string::npos, again.output);
  BOOST_TEST(count(again.output, "is up to date") == 3, again.output);
}

BOOST_AUTO_TEST_CASE(other_check_options_judge_again_and_the_same_do_not) {
  const auto judged = fs::last_write_time(kDir / "p" / "checks.json");
  const std::string args = pipeline_args() + " --alpha 0.2 --margin 0.3";
  const auto other = jam::test::run_jam_logged(kDir / "other.txt", args);
  BOOST_TEST(other.status == 0, other.output);
  BOOST_TEST(other.output.find("stats.h5 is up to date") != std::string::npos, other.output);
  BOOST_TEST(other.output.find("checks.json is up to date") == std::string::npos, other.output);
  BOOST_TEST(other.output.find("judged with other options") != std::string::npos, other.output);
  BOOST_TEST((fs::last_write_time(kDir / "p" / "checks.json") > judged));
  const auto options = checks_json()["options"];
  BOOST_TEST(options["alpha"] == 0.2, options.dump());
  BOOST_TEST(options["margin"] == 0.3, options.dump());
  BOOST_TEST(options["margins"]["finite_size"] == 0.3, options.dump());
  const nlohmann::json rejudged = checks_json();
  for (const auto& v : rejudged["verdicts"])
    if (v["check"] == "finite_size" && v["margin"].is_number())
      BOOST_TEST(v["margin"] == 0.3, v.dump());
  const auto same = jam::test::run_jam_logged(kDir / "same.txt", args);
  BOOST_TEST(same.status == 0, same.output);
  BOOST_TEST(count(same.output, "is up to date") == 3, same.output);
  // Back to the defaults: judged again.
  const auto back = jam::test::run_jam_logged(kDir / "back.txt", pipeline_args());
  BOOST_TEST(back.output.find("judged with other options") != std::string::npos, back.output);
  BOOST_TEST(checks_json()["options"]["alpha"] == 0.05);
}

BOOST_AUTO_TEST_CASE(with_lammps_judges_again_with_the_self_checks) {
  const auto asked = jam::test::run_jam_logged(kDir / "lammps.txt",
                                               pipeline_args() + " --with-lammps --reference-dir " +
                                                   std::string(JAM_SOURCE_DIR) + "/reference");
  BOOST_TEST(asked.status == 0, asked.output);
  BOOST_TEST(asked.output.find("judged with other options") != std::string::npos, asked.output);
  const nlohmann::json judged = checks_json();
  BOOST_TEST(judged["options"]["with_lammps"] == true);
  std::size_t lammps = 0;
  for (const auto& v : judged["verdicts"]) lammps += v["check"] == "lammps";
  BOOST_TEST(lammps == 18u);
  BOOST_TEST(asked.output.find("self-checks were not run") == std::string::npos, asked.output);
}

BOOST_AUTO_TEST_CASE(a_bad_check_option_is_one_line_naming_it_before_any_run) {
  const fs::path file = kDir / "fresh.toml", output = kDir / "fresh";
  std::ofstream(file) << campaign_text(output);
  for (const std::string bad :
       {"--alpha 2", "--alpha 0", "--margin 0", "--margin nan", "--permutations 5", "--phi-min 1.5",
        "--phi-min 0.8 --phi-max 0.7"}) {
    const auto o =
        jam::test::run_jam_logged(kDir / "bad.txt", "pipeline " + file.string() + " " + bad);
    BOOST_TEST(o.status == 2, bad << ": " << o.output);
    BOOST_TEST(count(o.output, "\n") == 1, bad << ": " << o.output);
    // The option named with its value (the last one given, for the pair).
    const std::string named = bad.substr(bad.rfind("--"));
    BOOST_TEST(o.output.find(named + ":") != std::string::npos, bad << ": " << o.output);
    BOOST_TEST(!fs::exists(output), bad << ": " << output);  // nothing run, nothing written
  }
}

BOOST_AUTO_TEST_CASE(check_prints_one_table_per_check_with_whole_case_names) {
  const fs::path dir = kDir / "p";
  const auto o =
      jam::test::run_jam_logged(kDir / "check.txt", "check all --no-lmp " + dir.string());
  BOOST_TEST((o.status == 0 || o.status == 1 || o.status == 3), o.output);
  std::set<std::string> checks;
  const nlohmann::json judged = checks_json();
  for (const auto& v : judged["verdicts"]) {
    checks.insert(v["check"].get<std::string>());
    // Under its numbers, the case whole at the start of a line, then its reason.
    const std::string at = "\n    " + v["case"].get<std::string>();
    BOOST_TEST((o.output.find(at + ": ") != std::string::npos ||
                o.output.find(at + "\n") != std::string::npos),
               v["case"] << "\n"
                         << o.output);
  }
  BOOST_TEST(o.output.find("...") == std::string::npos, o.output);
  std::istringstream lines(o.output);
  std::map<std::string, int> headings;
  for (std::string line; std::getline(lines, line);) {
    const auto colon = line.find(": ");
    if (colon != std::string::npos && checks.count(line.substr(0, colon))) {
      ++headings[line.substr(0, colon)];
      // The unit of the check's effects, said in its heading; relative ones in %.
      if (line.substr(0, colon) == "finite_size") BOOST_TEST(line.ends_with("effects in %"), line);
    }
    // No row of a table mixes a percent sign with its bare numbers: units are in the headings.
    if (line.rfind("  ", 0) == 0 && line.rfind("  effects in ", 0) != 0)
      BOOST_TEST(line.find('%') == std::string::npos, line);
  }
  for (const auto& c : checks) BOOST_TEST(headings[c] == 1, c << "\n" << o.output);
}

namespace {

using jam::test::wait_until;

/// Whether `file` is absent or was last written before `signalled`.
bool not_written_since(const fs::path& file, fs::file_time_type signalled) {
  return !fs::exists(file) || fs::last_write_time(file) < signalled;
}

/// The report's temporary directories (`<report>.<pid>.partial`, jamio.output) left in kDir.
std::size_t partial_reports(const std::string& report) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(kDir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(report + ".", 0) == 0 && name.ends_with(".partial")) ++n;
  }
  return n;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_first_sigterm_after_the_campaign_ends_it_with_130_writing_nothing) {
  const fs::path file = kDir / "sig.toml", output = kDir / "sig", report = kDir / "sig-report";
  std::ofstream(file) << campaign_text(output);
  const pid_t pid = jam::test::spawn_jam("pipeline " + file.string() +
                                         " --jobs 2 --no-lmp --report " + report.string());
  // manifest.toml is written once, when the campaign stage ends: then stats begins.
  BOOST_TEST_REQUIRE(wait_until([&] { return fs::exists(output / "manifest.toml"); }, pid));
  const auto signalled = fs::file_time_type::clock::now();
  ::kill(pid, SIGTERM);
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  BOOST_TEST(not_written_since(output / "stats.h5", signalled));
  BOOST_TEST(!fs::exists(output / "checks.json"));
  BOOST_TEST(!fs::exists(report));
  BOOST_TEST(partial_reports("sig-report") == 0u);
  // Run again, it goes on from there.
  const auto again = jam::test::run_jam_logged(
      kDir / "sig.txt",
      "pipeline " + file.string() + " --jobs 2 --no-lmp --report " + report.string());
  BOOST_TEST(again.status == 0, again.output);
  BOOST_TEST(fs::exists(report / "index.html"));
}

BOOST_AUTO_TEST_CASE(a_sigint_while_the_report_is_drawn_leaves_no_report) {
  // Stats and checks of p are up to date (the first case): the report is the one stage left.
  const fs::path report = kDir / "int-report";
  const pid_t pid = jam::test::spawn_jam("pipeline " + (kDir / "p.toml").string() +
                                         " --jobs 2 --no-lmp --report " + report.string());
  BOOST_TEST_REQUIRE(wait_until([&] { return partial_reports("int-report") > 0; }, pid));
  const auto checks = fs::last_write_time(kDir / "p" / "checks.json");
  ::kill(pid, SIGINT);
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  BOOST_TEST(!fs::exists(report));
  BOOST_TEST(partial_reports("int-report") == 0u);
  BOOST_TEST((fs::last_write_time(kDir / "p" / "checks.json") == checks));
}

// The stats stage is redone by the runs' digest, as `jam check` judges freshness: runs merely
// touched (newer modification times, the same content) leave every stage up to date; samples
// added to the campaign file are run, averaged again, judged again and drawn again.
BOOST_AUTO_TEST_CASE(stats_are_averaged_again_when_the_runs_change_not_when_touched) {
  const fs::path file = kDir / "digest.toml", output = kDir / "digest";
  auto campaign = [&](int samples) {
    std::ofstream(file) << "name = \"digest\"\ndim = 2\nsizes = [64]\nphi_init = [0.70]\n"
                           "log10_rates = [-2.5, -3.0]\nsamples = "
                        << samples
                        << "\nphi_stop = 0.80\nphi_step = 0.002\ndt = 0.02\nseed = 5\n"
                           "output = \""
                        << output.string() << "\"\n";
  };
  const std::string args = "pipeline " + file.string() + " --jobs 2 --no-lmp --report " +
                           (kDir / "digest-report").string();
  campaign(2);
  BOOST_TEST_REQUIRE(jam::test::run_jam_logged(kDir / "digest.txt", args).status == 0);
  const auto averaged = fs::last_write_time(output / "stats.h5");
  const auto later = fs::file_time_type::clock::now() + std::chrono::seconds(5);
  for (const auto& e : fs::directory_iterator(output / "runs"))
    fs::last_write_time(e.path(), later);
  const auto touched = jam::test::run_jam_logged(kDir / "digest.txt", args);
  BOOST_TEST(touched.status == 0, touched.output);
  BOOST_TEST(count(touched.output, "is up to date") == 3, touched.output);
  BOOST_TEST((fs::last_write_time(output / "stats.h5") == averaged));
  campaign(3);
  const auto added = jam::test::run_jam_logged(kDir / "digest.txt", args);
  BOOST_TEST(added.status == 0, added.output);
  BOOST_TEST(count(added.output, "is up to date") == 0, added.output);
  BOOST_TEST(added.output.find("6 runs averaged") != std::string::npos, added.output);
}
