// `jam campaign` end to end through the executable: a campaign runs, reruns do nothing,
// incompatible changes are refused, corrupt run files are detected and redone, a campaign
// killed (SIGKILL) at random moments finishes with run files identical to an uninterrupted
// one without redoing finished runs, and an MPI campaign equals the local one.
#include <signal.h>
#include <sys/wait.h>

#include <boost/test/unit_test.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/run/compression_run.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-campaign-" + std::to_string(::getpid()));

using jam::test::slurp;

using jam::test::Outcome;

Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

fs::path write_campaign(const std::string& name, const std::string& body) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << body << "output = \"" << (kDir / name).string() << "\"\n";
  return file;
}

// Run files of a campaign directory, by name.
std::map<std::string, std::string> run_files(const std::string& name) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(kDir / name / "runs")) {
    if (e.path().extension() == ".h5") files[e.path().filename().string()] = slurp(e.path());
  }
  return files;
}

const std::string kSmall = R"(name = "small"
dim = 2
sizes = [128, 256]
phi_init = [0.70, 0.80]
log10_rates = [-2.5, -3.0]
samples = 2
phi_stop = 0.86
phi_step = 0.002
dt = 0.02
seed = 11
)";

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

}  // namespace

BOOST_FIXTURE_TEST_SUITE(campaign, Fixture)

BOOST_AUTO_TEST_CASE(runs_reruns_refuses_and_repairs) {
  const fs::path file = write_campaign("a", kSmall);
  Outcome o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const auto first = run_files("a");
  BOOST_TEST(first.size() == 16u);
  BOOST_TEST(fs::exists(kDir / "a" / "manifest.toml"));
  {
    // Every done run's entry carries its record's cost and the version that ran it.
    const std::string manifest = slurp(kDir / "a" / "manifest.toml");
    auto count = [&](const std::string& pattern) {
      const std::regex re(pattern);
      return std::distance(std::sregex_iterator(manifest.begin(), manifest.end(), re),
                           std::sregex_iterator());
    };
    BOOST_TEST(count("status = 'done'") == 16);
    BOOST_TEST(count("cpu_seconds = [0-9]") == 16);
    BOOST_TEST(count("wall_seconds = [0-9]") == 16);
    BOOST_TEST(count("\\bversion = '0\\.1\\.0") == 16);
  }

  o = run_jam("campaign status " + (kDir / "a").string());
  BOOST_TEST(o.output.find("done     16") != std::string::npos, o.output);

  // Rerun: nothing to do, nothing touched.
  o = run_jam("campaign run " + file.string());
  BOOST_TEST(o.status == 0);
  BOOST_TEST(o.output.find("16 done, 0 to run") != std::string::npos, o.output);
  BOOST_TEST((run_files("a") == first));

  // An incompatible change is refused, naming what differs.
  std::string text = slurp(file);
  const fs::path changed = kDir / "changed.toml";
  std::ofstream(changed) << text.replace(text.find("dt = 0.02"), 9, "dt = 0.01");
  o = run_jam("campaign run " + changed.string());
  BOOST_TEST(o.status != 0);
  BOOST_TEST(o.output.find("differs in dt 0.02 -> 0.01") != std::string::npos, o.output);
  BOOST_TEST((run_files("a") == first));

  // A truncated run file is detected, never taken for a result, and redone identically.
  const fs::path victim = kDir / "a" / "runs" / "n256_phi0.7000_r-3.00_s001.h5";
  fs::resize_file(victim, fs::file_size(victim) / 2);
  o = run_jam("campaign status " + (kDir / "a").string());
  BOOST_TEST(o.output.find("corrupt  1") != std::string::npos, o.output);
  BOOST_TEST(o.output.find("n256_phi0.7000_r-3.00_s001") != std::string::npos, o.output);
  o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST(o.status == 0);
  BOOST_TEST((run_files("a") == first));

  // Each run file is exactly what a single `jam sim` run (no shared start) gives for its seed,
  // whether its relaxed start came from the cache or not.
  // (named for the integrator unless Heun, the default of the version that introduced them)
  BOOST_TEST(fs::exists(kDir / "a" / "starts" / "n128_phi0.8000_s001_chebyshev.h5"));
  for (auto [name, phi_init] : {std::pair{"n128_phi0.8000_r-2.50_s001", 0.80},
                                std::pair{"n256_phi0.7000_r-3.00_s000", 0.70}}) {
    const fs::path run = kDir / "a" / "runs" / (std::string(name) + ".h5");
    jam::SimConfig c;
    c.phi_init = phi_init;  // as in the campaign file (the stored one is the packing reached)
    {
      const jam::h5::File f = jam::h5::File::open_read(run.string());
      c.n = f.read_attribute_int("n");
      c.compression_rate = f.read_attribute_double("compression_rate");
      c.seed = static_cast<std::uint64_t>(f.read_attribute_int("seed"));
      c.campaign = f.read_attribute_string("campaign");  // where it belongs, not its physics
      c.sample = f.read_attribute_int("sample");
    }
    BOOST_TEST(c.campaign == "small");
    BOOST_TEST(c.sample == std::stoll(std::string(name).substr(std::string(name).size() - 3)));
    c.phi_stop = 0.86;
    c.phi_step = 0.002;
    c.dt = 0.02;
    c.relax_energy = "1e-14";
    c.quiet = true;
    c.checkpoint_interval = 0;
    c.out = (kDir / "single.h5").string();
    jam::run_compression(c);
    BOOST_TEST((slurp(c.out) == slurp(run)), name);
  }

  // Adding a rate only adds runs.
  std::string more = kSmall;
  more.replace(more.find("[-2.5, -3.0]"), 12, "[-2.5, -3.0, -2.0]");
  o = run_jam("campaign run --quiet " + write_campaign("a", more).string());
  BOOST_TEST(o.status == 0);
  const auto grown = run_files("a");
  BOOST_TEST(grown.size() == 24u);
  for (const auto& [name, bytes] : first) BOOST_TEST((grown.at(name) == bytes), name);
}

// Without a terminal (a Slurm log) a campaign writes a dated progress line every --log-every
// seconds: runs done of the total, core-hours, speed, ETA; with --quiet none.
BOOST_AUTO_TEST_CASE(progress_lines_in_a_log_without_a_terminal) {
  const fs::path file = write_campaign("logged", R"(name = "logged"
dim = 2
sizes = [512]
phi_init = [0.75]
log10_rates = [-3.0]
samples = 8
phi_stop = 0.86
seed = 9
)");
  const Outcome o = run_jam("campaign run --jobs 1 --log-every 0.1 " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const std::regex line(
      R"(jam: \d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ campaign logged: runs \d+/8 done, [0-9.e+-]+ )"
      R"(core-hours, [0-9.e+-]+ particle-steps/s, ETA .+)");
  std::istringstream lines(o.output);
  int progress = 0;
  for (std::string l; std::getline(lines, l);) progress += std::regex_match(l, line);
  BOOST_TEST(progress >= 1, o.output);
  fs::remove_all(kDir / "logged");
  const Outcome quiet = run_jam("campaign run --quiet --log-every 0.1 " + file.string());
  BOOST_TEST(quiet.output.find("core-hours") == std::string::npos, quiet.output);
}

BOOST_AUTO_TEST_CASE(killed_campaign_resumes_to_identical_files) {
  const std::string body = R"(name = "kill"
dim = 2
sizes = [512, 1024]
phi_init = [0.75]
log10_rates = [-2.5, -3.0]
samples = 2
phi_stop = 0.86
dt = 0.02
seed = 3
checkpoint_interval = 0.02
)";
  const fs::path reference = write_campaign("reference", body);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + reference.string()).status == 0);
  const auto expected = run_files("reference");

  const fs::path file = write_campaign("killed", body);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> extra_ms(0, 150);
  std::map<std::string, fs::file_time_type> finished;  // run file -> time it was written
  int kills = 0;
  for (int attempt = 0; attempt < 6; ++attempt) {
    // Killed once it has written something new (a checkpoint or a run file), and a random
    // moment after that: the kill lands mid-campaign however fast the machine is, with no
    // assumption on how long a run takes.
    const auto since = fs::file_time_type::clock::now();
    const pid_t pid = jam::test::spawn_jam("campaign run --quiet " + file.string());
    if (!jam::test::wrote_since(kDir / "killed" / "runs", since, pid)) {
      if (jam::test::wait_for(pid) >= 0) break;  // finished with nothing new to write
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(extra_ms(rng)));
    kill(pid, SIGKILL);
    if (jam::test::wait_for(pid) >= 0) break;  // finished before the kill
    ++kills;
    // Finished runs are never redone: their files keep the time they were first written.
    for (const auto& e : fs::directory_iterator(kDir / "killed" / "runs")) {
      if (e.path().extension() != ".h5") continue;
      const auto name = e.path().filename().string();
      const auto written = fs::last_write_time(e.path());
      if (finished.count(name)) BOOST_TEST((finished[name] == written), name << " was redone");
      finished[name] = written;
    }
  }
  BOOST_TEST(kills >= 2);
  const Outcome o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const auto got = run_files("killed");
  BOOST_TEST(got.size() == expected.size());
  for (const auto& [name, bytes] : expected) {
    BOOST_TEST((got.count(name) && got.at(name) == bytes), name << " differs");
  }
  for (const auto& e : fs::directory_iterator(kDir / "killed" / "runs")) {
    BOOST_TEST(e.path().extension() != ".checkpoint", "stale " << e.path());
    BOOST_TEST(e.path().string().find(".partial") == std::string::npos, "stale " << e.path());
  }
}

BOOST_AUTO_TEST_CASE(mpi_campaign_equals_local) {
  if (jam::find_program("mpirun").empty()) {
    BOOST_TEST_MESSAGE("mpirun not installed: skipped");
    return;
  }
  const fs::path local = write_campaign("local", kSmall);
  const Outcome first = run_jam("campaign run --quiet --jobs 2 " + local.string());
  BOOST_TEST_REQUIRE(first.status == 0, first.output);
  const fs::path distributed = write_campaign("mpi", kSmall);
  const fs::path log = kDir / "mpi.txt";
  // As root OpenMPI also needs these two variables.
  const std::vector<std::string> argv = {"env",
                                         "OMPI_ALLOW_RUN_AS_ROOT=1",
                                         "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                                         "mpirun",
                                         "-n",
                                         "2",
                                         "--oversubscribe",
                                         JAM_EXECUTABLE,
                                         "campaign",
                                         "run",
                                         "--jobs",
                                         "2",
                                         distributed.string()};
  BOOST_TEST_REQUIRE(jam::test::run_logged(log, argv).status == 0, slurp(log));
  const std::string text = slurp(log);
  BOOST_TEST(text.find("on 2 ranks") != std::string::npos, text);
  BOOST_TEST((run_files("mpi") == run_files("local")));
  // 16 runs of uneven cost (N 128 and 256, two rates) for 2 ranks x 2 workers: rank 0 hands
  // them out as workers ask; every run is taken exactly once, and both ranks take some.
  int total = 0;
  for (int rank : {0, 1}) {
    const std::string key = "rank " + std::to_string(rank) + ": took ";
    const auto at = text.find(key);
    BOOST_TEST_REQUIRE(at != std::string::npos, text);
    const int taken = std::stoi(text.substr(at + key.size()));
    BOOST_TEST(taken > 0, text);
    total += taken;
  }
  BOOST_TEST(total == 16, text);
  BOOST_TEST(text.find("handed out as workers became free") != std::string::npos, text);
}

BOOST_AUTO_TEST_CASE(shipped_campaigns_parse_and_cost) {
  int shipped = 0;
  for (const auto& e : fs::directory_iterator(fs::path(JAM_SOURCE_DIR) / "reference/campaigns")) {
    if (e.path().extension() != ".toml") continue;
    ++shipped;
    const Outcome o = run_jam("campaign plan " + e.path().string());
    BOOST_TEST(o.status == 0, e.path() << ": " << o.output);
    BOOST_TEST(o.output.find("core-hours") != std::string::npos, o.output);
  }
  BOOST_TEST(shipped >= 10);
}

BOOST_AUTO_TEST_SUITE_END()
