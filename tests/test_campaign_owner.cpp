// One owner per campaign directory, and a run file counts as done only when it is the planned
// run's. A second `jam campaign run` on a directory in use stops at once naming the owner (it
// neither redoes runs nor trips over the first runner's temporary files); two started together
// leave one complete, consistent campaign. With campaign.toml deleted, a rerun at another dt
// does not take the old runs for its own: they are set aside (never deleted) and redone, and
// `jam stats` averages only runs of the planned parameters. The owner removes only jam's own
// temporaries.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "campaign/campaign_lock.hpp"
#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/run_file.hpp"

namespace fs = std::filesystem;
using jam::test::Outcome;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-owner-" + std::to_string(::getpid()));

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

const std::string kSmall = R"(name = "owner"
dim = 2
sizes = [64]
phi_init = [0.70]
log10_rates = [-2.5]
samples = 6
phi_stop = 0.80
phi_step = 0.005
relax_energy = "1e-12"
seed = 5
)";

fs::path write_campaign(const std::string& name, const std::string& body, const fs::path& out) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << body << "output = \"" << out.string() << "\"\n";
  return file;
}

Outcome run_jam(const std::string& args, const std::string& log = "log.txt") {
  return jam::test::run_jam_logged(kDir / log, args);
}

std::map<std::string, std::string> run_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    if (e.path().extension() == ".h5") files[e.path().filename().string()] = slurp(e.path());
  }
  return files;
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(owner, Fixture)

BOOST_AUTO_TEST_CASE(second_runner_is_refused_naming_the_owner) {
  const fs::path dir = kDir / "held";
  fs::create_directories(dir);
  const fs::path file = write_campaign("held", kSmall, dir);
  {
    const jam::CampaignLock held(dir.string());
    const Outcome o = run_jam("campaign run --quiet " + file.string());
    BOOST_TEST(o.status == 2, o.output);
    BOOST_TEST(o.output.find("in use by pid " + std::to_string(::getpid())) != std::string::npos,
               o.output);
    BOOST_TEST(std::count(o.output.begin(), o.output.end(), '\n') == 1, o.output);
    BOOST_TEST(!fs::exists(dir / "runs"));  // nothing done, nothing written
    BOOST_CHECK_THROW(jam::CampaignLock again(dir.string()), jam::CampaignError);
  }
  // Released with its owner: the campaign runs.
  BOOST_TEST(run_jam("campaign run --quiet " + file.string()).status == 0);
}

// Two runners started together, repeatedly: each either does the campaign or is refused;
// neither fails on the other's files; the directory ends complete and bitwise like a single
// runner's.
BOOST_AUTO_TEST_CASE(two_runners_at_once) {
  const fs::path single = kDir / "single";
  BOOST_REQUIRE(
      run_jam("campaign run --quiet " + write_campaign("s", kSmall, single).string()).status == 0);
  const auto expected = run_files(single);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const fs::path dir = kDir / ("race" + std::to_string(attempt));
    const fs::path file = write_campaign("r", kSmall, dir);
    const pid_t first = jam::test::spawn_jam("campaign run --quiet " + file.string());
    const pid_t second = jam::test::spawn_jam("campaign run --quiet " + file.string());
    const int s1 = jam::test::wait_for(first), s2 = jam::test::wait_for(second);
    BOOST_TEST_CONTEXT("attempt " << attempt << ": exit " << s1 << " and " << s2) {
      BOOST_TEST(((s1 == 0 && (s2 == 0 || s2 == 2)) || (s2 == 0 && s1 == 2)));
      BOOST_TEST((run_files(dir) == expected));
      for (const auto& e : fs::directory_iterator(dir / "runs")) {
        BOOST_TEST(e.path().string().find(".partial") == std::string::npos, e.path());
      }
    }
  }
}

// A runner that owns the whole directory removes the temporaries a killed jam left
// ("<name>.<pid>-<tid>.partial", AtomicFile's names) in the directory, runs/, starts/ and
// chain/, and nothing else: a user's "x.partial", a name without the pid-tid part, and a
// directory named like a temporary stay where they are.
BOOST_AUTO_TEST_CASE(only_jams_own_temporaries_are_removed) {
  const fs::path dir = kDir / "temporaries";
  const fs::path file = write_campaign("temporaries", kSmall, dir);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const std::vector<fs::path> stale = {dir / "manifest.toml.123-456.partial",
                                       dir / "runs" / "n64_phi0.7000_r-2.50_s000.h5.7-8.partial",
                                       dir / "starts" / "s000.h5.99-1.partial",
                                       dir / "chain" / "c.h5.5-6.partial"};
  const std::vector<fs::path> kept = {dir / "notes.partial", dir / "runs" / "x.partial",
                                      dir / "runs" / "a.h5.partial", dir / "runs" / "b.7.partial",
                                      dir / "starts" / "s.h5.1-x.partial"};
  for (const auto& f : stale) {
    fs::create_directories(f.parent_path());
    std::ofstream(f) << "left by a killed jam\n";
  }
  for (const auto& f : kept) std::ofstream(f) << "the user's\n";
  const fs::path folder = dir / "runs" / "saved.1-2.partial";
  fs::create_directories(folder);
  BOOST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  for (const auto& f : stale) BOOST_TEST(!fs::exists(f), f);
  for (const auto& f : kept) BOOST_TEST(slurp(f) == "the user's\n", f);
  BOOST_TEST(fs::is_directory(folder));
}

BOOST_AUTO_TEST_CASE(runs_of_other_parameters_are_not_taken_for_done) {
  const fs::path dir = kDir / "mixed";
  std::string coarse = kSmall;
  coarse += "dt = 0.1\n";
  BOOST_REQUIRE(
      run_jam("campaign run --quiet " + write_campaign("m", coarse, dir).string()).status == 0);
  fs::remove(dir / "campaign.toml");
  fs::remove(dir / "manifest.toml");

  std::string fine = kSmall;
  fine += "dt = 0.05\n";
  const fs::path file = write_campaign("m", fine, dir);
  Outcome o = run_jam("campaign status " + dir.string());  // status reads campaign.toml
  BOOST_TEST(o.status != 0);
  o = run_jam("campaign run --quiet " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  std::size_t rejected = 0;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    if (e.path().extension() == ".rejected") ++rejected;  // set aside, not deleted
  }
  BOOST_TEST(rejected == 6u);
  for (const auto& [name, bytes] : run_files(dir)) {
    BOOST_TEST(
        jam::h5::File::open_read((dir / "runs" / name).string()).read_attribute_double("dt") ==
            0.05,
        name);
  }
  o = run_jam("stats --no-fit " + dir.string());
  BOOST_TEST(o.output.find("6 runs averaged, 0 skipped") != std::string::npos, o.output);
}

// Shares of a campaign (`--shard K/N`, one per job of a Slurm array): disjoint, together the
// whole campaign bitwise, side by side in one directory; an unsharded runner excludes them.
BOOST_AUTO_TEST_CASE(shards_make_the_whole_campaign) {
  const fs::path single = kDir / "single";
  BOOST_REQUIRE(
      run_jam("campaign run --quiet " + write_campaign("s", kSmall, single).string()).status == 0);
  const auto expected = run_files(single);

  const fs::path dir = kDir / "shards";
  const fs::path file = write_campaign("h", kSmall, dir);
  std::size_t before = 0;
  for (int k = 1; k <= 3; ++k) {
    const Outcome o =
        run_jam("campaign run --quiet --shard " + std::to_string(k) + "/3 " + file.string());
    BOOST_TEST(o.status == 0, o.output);
    const std::size_t now = run_files(dir).size();
    BOOST_TEST(now > before);  // every share did some of the work ...
    before = now;
  }
  BOOST_TEST((run_files(dir) == expected));  // ... and together all of it

  // Two shares at once in a fresh directory.
  const fs::path both = kDir / "both";
  const fs::path file2 = write_campaign("b", kSmall, both);
  const pid_t a = jam::test::spawn_jam("campaign run --quiet --shard 1/2 " + file2.string());
  const pid_t b = jam::test::spawn_jam("campaign run --quiet --shard 2/2 " + file2.string());
  BOOST_TEST(jam::test::wait_for(a) == 0);
  BOOST_TEST(jam::test::wait_for(b) == 0);
  BOOST_TEST((run_files(both) == expected));

  {  // A share is refused while the whole directory is owned, and the other way round.
    const jam::CampaignLock whole(dir.string());
    BOOST_TEST(run_jam("campaign run --quiet --shard 1/2 " + file.string()).status == 2);
  }
  {
    const jam::CampaignLock share(dir.string(), "1-of-2");
    BOOST_TEST(run_jam("campaign run --quiet " + file.string()).status == 2);
    BOOST_TEST(run_jam("campaign run --quiet --shard 2/2 " + file.string()).status == 0);
    BOOST_TEST(run_jam("campaign run --quiet --shard 1/2 " + file.string()).status == 2);
  }
  for (const char* bad : {"0/2", "3/2", "1/0", "x", "1/2/3"}) {
    const Outcome o =
        run_jam(std::string("campaign run --quiet --shard ") + bad + " " + file.string());
    BOOST_TEST(o.status == 2, bad);
    BOOST_TEST(o.output.find("--shard") != std::string::npos, o.output);
  }
}

// `--shard auto`: the share of a Slurm array task from SLURM_ARRAY_TASK_ID, _COUNT, _MIN and
// _STEP, so that arrays numbered from 0 (--array=0-2), from 1, or with a step (--array=1-5:2)
// each make the whole campaign; outside an array it is refused in one line naming the variable.
BOOST_AUTO_TEST_CASE(shard_auto_follows_the_slurm_array_numbering) {
  const fs::path single = kDir / "auto-single";
  BOOST_REQUIRE(
      run_jam("campaign run --quiet " + write_campaign("s", kSmall, single).string()).status == 0);
  const auto expected = run_files(single);
  struct Array {
    const char* name;
    std::vector<int> ids;
    int first, step;
  };
  for (const Array& array : {Array{"zero", {0, 1, 2}, 0, 1}, Array{"stepped", {1, 3, 5}, 1, 2}}) {
    const fs::path dir = kDir / (std::string("auto-") + array.name);
    const fs::path file = write_campaign(array.name, kSmall, dir);
    for (const int id : array.ids) {
      std::vector<std::string> argv = {"env", "SLURM_ARRAY_TASK_ID=" + std::to_string(id),
                                       "SLURM_ARRAY_TASK_COUNT=" + std::to_string(array.ids.size()),
                                       "SLURM_ARRAY_TASK_MIN=" + std::to_string(array.first),
                                       "SLURM_ARRAY_TASK_STEP=" + std::to_string(array.step)};
      for (auto& w : jam::test::jam_argv("campaign run --quiet --shard auto " + file.string())) {
        argv.push_back(w);
      }
      const Outcome o = jam::test::run_logged(kDir / "auto.txt", argv);
      BOOST_TEST(o.status == 0, array.name << " task " << id << ": " << o.output);
    }
    BOOST_TEST((run_files(dir) == expected), array.name);
  }
  const Outcome outside = run_jam("campaign run --quiet --shard auto " +
                                  write_campaign("o", kSmall, kDir / "auto-outside").string());
  BOOST_TEST(outside.status == 2, outside.output);
  BOOST_TEST(outside.output.find("SLURM_ARRAY_TASK_ID is not set") != std::string::npos,
             outside.output);
}

BOOST_AUTO_TEST_SUITE_END()
