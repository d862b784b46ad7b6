// `jam campaign run --until-decided --budget H` through the executable: a bad budget is one
// line naming --budget and nothing is run; a small two-size campaign runs look after look
// until its verdicts are decided, and the same command in another directory gives the same
// verdicts and added samples; killed (SIGKILL) in the middle of a later look and run again it
// ends with the same files; two shards run at once, and under mpirun two ranks, end with the
// same verdicts too; a tight budget stops it and says so. Run again with another alpha or
// margin it refuses, naming both values; resumed with a smaller budget it runs none of the
// pending batch; a SIGTERM while a look is judged ends it with 130 and nothing of the look.
#include <signal.h>
#include <sys/wait.h>

#include <boost/test/unit_test.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include "process.hpp"
#include "scratch.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("until");

using jam::test::Outcome;
using jam::test::slurp;

Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

// Two small sizes at two fast rates: four samples decide little, so the sequence takes several
// looks (each a few seconds on one core; five at the finite-size margin of 0.15, at 0.1 it
// takes seven, the N = 64 set growing to about 160 samples).
fs::path write_campaign(const std::string& name) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << "name = \"ud\"\ndim = 2\nsizes = [64, 128]\nphi_init = [0.70]\n"
                         "log10_rates = [-2.5, -3.0]\nsamples = 4\nphi_stop = 0.86\n"
                         "phi_step = 0.002\ndt = 0.02\nseed = 5\n"
                      << "output = \"" << (kDir / name).string() << "\"\n"
                      << "[margins]\nfinite_size = 0.15\n";
  return file;
}

/// checks.json without the line that says when it was written.
std::string verdicts(const std::string& name) {
  const std::string text = slurp(kDir / name / "checks.json");
  return std::regex_replace(text, std::regex("\"created\": \"[^\"]*\""), "");
}

/// What a sequence decided: its verdicts and the samples it added.
std::string outcome(const std::string& name) {
  return verdicts(name) + slurp(kDir / name / "added-samples.toml");
}

const std::string kArgs = " --until-decided --budget 1 --jobs 1 --quiet";

/// The sequence run once, uninterrupted, in directory "a" (the others compare with it).
const Outcome& uninterrupted() {
  static const Outcome a = run_jam("campaign run " + write_campaign("a").string() + kArgs);
  return a;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_bad_budget_is_one_line_and_runs_nothing) {
  const fs::path file = write_campaign("bad");
  for (const std::string budget :
       {"--budget 0", "--budget -1", "--budget nan", "--budget inf", ""}) {
    const Outcome o = run_jam("campaign run --until-decided " + budget + " " + file.string());
    BOOST_TEST(o.status == 2, budget << ": " << o.output);
    BOOST_TEST(o.output.find("--budget") != std::string::npos, budget << ": " << o.output);
    BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') == 1, o.output);
    BOOST_TEST(!fs::exists(kDir / "bad"), budget);
  }
  const Outcome o = run_jam("campaign run --budget 1 " + file.string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(!fs::exists(kDir / "bad"));
}

BOOST_AUTO_TEST_CASE(decided_deterministically_and_resumed_after_kill) {
  const std::string& args = kArgs;
  const Outcome& a = uninterrupted();
  // 0 all pass, 3: verdicts samples cannot decide (a single phi_init, no fit for zeta) stay.
  BOOST_TEST_REQUIRE((a.status == 0 || a.status == 3), a.output);
  BOOST_TEST(a.output.find("every verdict decided at look") != std::string::npos, a.output);
  BOOST_TEST(a.output.find("look 2 at alpha 0.00833") != std::string::npos, a.output);
  BOOST_TEST(verdicts("a").find("\"look\": 1.0") != std::string::npos);

  // Killed once the second look's runs have begun, then run again.
  const fs::path b = write_campaign("b");
  const pid_t pid = jam::test::spawn_jam("campaign run " + b.string() + args);
  const fs::path state = kDir / "b" / "until-decided.json";
  for (int k = 0; k < 6000 && !fs::exists(state); ++k) usleep(10000);
  BOOST_TEST_REQUIRE(fs::exists(state));
  jam::test::wrote_since(kDir / "b" / "runs", fs::last_write_time(state), pid);
  kill(pid, SIGKILL);
  jam::test::wait_for(pid);
  const Outcome resumed = run_jam("campaign run " + b.string() + args);
  BOOST_TEST(resumed.status == a.status, resumed.output);
  BOOST_TEST(outcome("b") == outcome("a"));
  // Run once more, it finds the sequence finished and changes nothing.
  const auto before = fs::last_write_time(kDir / "b" / "checks.json");
  const Outcome again = run_jam("campaign run " + b.string() + args);
  BOOST_TEST(again.status == a.status, again.output);
  BOOST_TEST(again.output.find("every verdict decided") != std::string::npos, again.output);
  BOOST_TEST((fs::last_write_time(kDir / "b" / "checks.json") == before));
}

BOOST_AUTO_TEST_CASE(shards_and_ranks_decide_alike) {
  const std::string& args = kArgs;
  const Outcome& a = uninterrupted();
  BOOST_TEST_REQUIRE((a.status == 0 || a.status == 3), a.output);
  const fs::path s = write_campaign("shards");
  const pid_t second = jam::test::spawn_jam("campaign run --shard 2/2 " + s.string() + args);
  const Outcome first = run_jam("campaign run --shard 1/2 " + s.string() + args);
  BOOST_TEST(first.status == a.status, first.output);
  BOOST_TEST(jam::test::wait_for(second) == 0);
  BOOST_TEST(outcome("shards") == outcome("a"));
  if (jam::find_program("mpirun").empty()) {
    BOOST_TEST_MESSAGE("mpirun not installed: the MPI part skipped");
    return;
  }
  const fs::path m = write_campaign("mpi");
  const fs::path log = kDir / "mpi.txt";
  std::vector<std::string> argv = {"env",
                                   "OMPI_ALLOW_RUN_AS_ROOT=1",
                                   "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                                   "mpirun",
                                   "-n",
                                   "2",
                                   "--oversubscribe",
                                   JAM_EXECUTABLE,
                                   "campaign",
                                   "run",
                                   m.string()};
  for (const auto& w : jam::test::words(args)) argv.push_back(w);
  const int status = jam::test::run_logged(log, argv).status;
  BOOST_TEST((status == 0 || status == 3), slurp(log));
  BOOST_TEST(outcome("mpi") == outcome("a"), slurp(log));
}

BOOST_AUTO_TEST_CASE(a_tight_budget_stops_and_says_so) {
  const Outcome o = run_jam("campaign run " + write_campaign("tight").string() +
                            " --until-decided --budget 0.00001 --jobs 1 --quiet");
  BOOST_TEST(o.status == 3, o.output);
  BOOST_TEST(o.output.find("budget spent at look 1") != std::string::npos, o.output);
  BOOST_TEST(fs::exists(kDir / "tight" / "checks.json"));
}

namespace {

using jam::test::wait_until;

std::size_t run_files(const std::string& name) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(kDir / name / "runs"))
    if (e.path().extension() == ".h5") ++n;
  return n;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_finished_sequence_refuses_other_options_naming_both_values) {
  const Outcome& a = uninterrupted();
  BOOST_TEST_REQUIRE((a.status == 0 || a.status == 3), a.output);
  const auto before = fs::last_write_time(kDir / "a" / "checks.json");
  const std::string file = (kDir / "a.toml").string();
  const Outcome alpha = run_jam("campaign run " + file +
                                " --until-decided --budget 1 --alpha 0.001 --jobs 1 --quiet");
  BOOST_TEST(alpha.status == 2, alpha.output);
  BOOST_TEST(std::count(alpha.output.begin(), alpha.output.end(), '\n') == 1, alpha.output);
  BOOST_TEST(alpha.output.find("--alpha 0.001 differs from the 0.05") != std::string::npos,
             alpha.output);
  BOOST_TEST(alpha.output.find("every verdict decided") == std::string::npos, alpha.output);
  // The margin 10x tighter in the campaign file: refused, naming the check and both margins.
  const fs::path tight = kDir / "a-tight.toml";
  std::string text = slurp(file);
  text.replace(text.find("finite_size = 0.15"), 18, "finite_size = 0.015");
  std::ofstream(tight) << text;
  const Outcome margin = run_jam("campaign run " + tight.string() + kArgs);
  BOOST_TEST(margin.status == 2, margin.output);
  BOOST_TEST(margin.output.find("the margin of finite_size (the campaign file's [margins]) "
                                "0.015 differs from the 0.15") != std::string::npos,
             margin.output);
  BOOST_TEST((fs::last_write_time(kDir / "a" / "checks.json") == before));
}

BOOST_AUTO_TEST_CASE(a_resumed_batch_is_held_to_the_budget_given_then) {
  const Outcome& a = uninterrupted();
  BOOST_TEST_REQUIRE((a.status == 0 || a.status == 3), a.output);
  const fs::path file = write_campaign("budget");
  const pid_t pid = jam::test::spawn_jam("campaign run " + file.string() + kArgs);
  const fs::path state = kDir / "budget" / "until-decided.json";
  BOOST_TEST_REQUIRE(wait_until([&] { return fs::exists(state); }, pid));
  kill(pid, SIGTERM);  // the second look's runs stop at their checkpoints
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  const std::size_t done = run_files("budget");
  const Outcome tiny = run_jam("campaign run " + file.string() +
                               " --until-decided --budget 1e-300 --jobs 1 --quiet");
  BOOST_TEST((tiny.status == 1 || tiny.status == 3), tiny.output);
  BOOST_TEST(
      tiny.output.find("would exceed the --budget of 1e-300 core-hours") != std::string::npos,
      tiny.output);
  BOOST_TEST(run_files("budget") == done);  // not one run of the batch
  // The budget it was planned with goes on with it, to the uninterrupted sequence's end.
  const Outcome resumed = run_jam("campaign run " + file.string() + kArgs);
  BOOST_TEST(resumed.status == a.status, resumed.output);
  BOOST_TEST(outcome("budget") == outcome("a"));
}

BOOST_AUTO_TEST_CASE(a_stop_while_a_look_is_judged_writes_nothing_of_the_look) {
  const fs::path file = write_campaign("stop");
  const pid_t pid = jam::test::spawn_jam("campaign run " + file.string() + kArgs);
  // manifest.toml is first written when the first look's runs have ended: then it judges.
  BOOST_TEST_REQUIRE(wait_until([&] { return fs::exists(kDir / "stop" / "manifest.toml"); }, pid));
  const auto signalled = fs::file_time_type::clock::now();
  kill(pid, SIGTERM);
  BOOST_TEST(jam::test::wait_for(pid) == 130);
  BOOST_TEST(!fs::exists(kDir / "stop" / "until-decided.json"));
  BOOST_TEST(!fs::exists(kDir / "stop" / "checks.json"));
  const fs::path stats = kDir / "stop" / "stats.h5";
  BOOST_TEST((!fs::exists(stats) || fs::last_write_time(stats) < signalled));
}

// The question in the campaign file ([question] phi_min, phi_max): --until-decided takes
// --phi-min/--phi-max (once refused as "not expected"), judges the range asked as the region
// "asked", records it in its state and in checks.json, and refuses to go on with another one,
// naming both values, in one line.
BOOST_AUTO_TEST_CASE(the_range_asked_is_taken_recorded_and_a_changed_one_refused) {
  const fs::path file = kDir / "asked.toml";
  std::ofstream(file) << slurp(write_campaign("asked"))
                      << "[question]\nphi_min = 0.80\nphi_max = 0.84\n";
  const std::string tight = " --until-decided --budget 0.00001 --jobs 1 --quiet";
  const Outcome o = run_jam("campaign run " + file.string() + tight + " --phi-min 0.78");
  BOOST_TEST(o.status == 3, o.output);  // the budget spent at look 1
  BOOST_TEST(o.output.find("look 1 at alpha 0.025 over the range asked, phi in [0.78, 0.84]") !=
                 std::string::npos,
             o.output);
  const std::string state = slurp(kDir / "asked" / "until-decided.json");
  BOOST_TEST(std::regex_search(state, std::regex("\"question\": \\{\\s*\"phi_max\": 0\\.84,\\s*"
                                                 "\"phi_min\": 0\\.78\\s*\\}")),
             state);
  const std::string checks = verdicts("asked");
  BOOST_TEST(checks.find("\"region\": \"asked\"") != std::string::npos);
  // At the top level of checks.json (two spaces in), the range and where it was stated.
  BOOST_TEST(std::regex_search(checks, std::regex("\n  \"question\": \\{[\\s\\S]*?\"range\": "
                                                  "\\{\\s*\"from\": \"\\[question\\] phi_min, "
                                                  "phi_max with --phi-min or --phi-max\",\\s*"
                                                  "\"phi_max\": 0\\.84,\\s*\"phi_min\": 0\\.78")),
             checks);
  const auto before = fs::last_write_time(kDir / "asked" / "checks.json");
  // Another range: refused, naming the key and both values, nothing rewritten.
  const Outcome changed =
      run_jam("campaign run " + file.string() + tight + " --phi-min 0.78 " + "--phi-max 0.85");
  BOOST_TEST(changed.status == 2, changed.output);
  BOOST_TEST(std::count(changed.output.begin(), changed.output.end(), '\n') == 1, changed.output);
  BOOST_TEST(
      changed.output.find("the range asked's phi_max ([question] phi_max, or --phi-max) "
                          "0.85 differs from the 0.84 it was begun with") != std::string::npos,
      changed.output);
  // The file's own range (without --phi-min) is another one too.
  const Outcome file_range = run_jam("campaign run " + file.string() + tight);
  BOOST_TEST(file_range.status == 2, file_range.output);
  BOOST_TEST(file_range.output.find("phi_min ([question] phi_min, or --phi-min) 0.8 differs "
                                    "from the 0.78") != std::string::npos,
             file_range.output);
  BOOST_TEST((fs::last_write_time(kDir / "asked" / "checks.json") == before));
  // A range that is none, and the options without --until-decided: one line each, no run.
  const Outcome none = run_jam("campaign run " + file.string() + tight + " --phi-max 0.7");
  BOOST_TEST(none.status == 2, none.output);
  BOOST_TEST(none.output.find("--phi-max 0.7: must exceed phi_min 0.8") != std::string::npos,
             none.output);
  const Outcome alone = run_jam("campaign run " + file.string() + " --phi-min 0.8 --quiet");
  BOOST_TEST(alone.status == 2, alone.output);
  BOOST_TEST(alone.output.find("go with --until-decided") != std::string::npos, alone.output);
}
