// Chained starts (campaign key chain_phi_init): each slower rate continues from the next faster
// run of its sample. The chain gives the numbers of the same two steps done by hand with
// `jam sim --write-start / --read-start`; a chained run waits for its parent; a missing or
// damaged start makes its parent run again first (a done parent only to the start: its run file
// stays), with identical results; lost starts of a whole chain (a run directory restored from
// its run files alone) are left again by each ancestor in turn; a parent that failed
// holds its children back; bad chain_phi_init values are refused naming the key; the plan
// states the saving.
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <map>

#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"
#include "process.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;
using jam::test::Outcome;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-chains-" + std::to_string(::getpid()));

Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

// Three rates of two samples: 1e-3 from the relaxed start at 0.70, 1e-4 from 1e-3's
// configuration at 0.80, 10^-4.5 from 1e-4's at 0.82.
const std::string kChain = R"(name = "chain"
dim = 2
sizes = [256]
phi_init = [0.70]
log10_rates = [-3.0, -4.0, -4.5]
chain_phi_init = [0, 0.80, 0.82]
samples = 2
phi_stop = 0.85
phi_step = 0.002
relax_energy = "1e-14"
seed = 5
)";

fs::path write_campaign(const std::string& name, const std::string& body) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << body << "output = \"" << (kDir / name).string() << "\"\n";
  return file;
}

std::map<std::string, std::string> run_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    if (e.path().extension() == ".h5") files[e.path().filename().string()] = slurp(e.path());
  }
  return files;
}

std::vector<double> dataset(const fs::path& file, const std::string& name) {
  return jam::h5::File::open_read(file.string()).read_dataset(name);
}

std::string campaign_rejection(const std::string& text) {
  try {
    jam::parse_campaign(text + "output = \"x\"\n", "c.toml");
  } catch (const jam::CampaignError& e) {
    return e.what();
  }
  return "accepted";
}

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

}  // namespace

BOOST_FIXTURE_TEST_SUITE(chains, Fixture)

BOOST_AUTO_TEST_CASE(a_chain_is_the_same_two_steps_by_hand) {
  const fs::path file = write_campaign("c", kChain);
  Outcome o = run_jam("campaign run --quiet --jobs 2 " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const fs::path runs = kDir / "c" / "runs";
  const jam::Campaign campaign = jam::read_campaign(file.string());
  std::map<std::string, jam::PlannedRun> plan;
  for (auto& r : jam::plan_runs(campaign)) plan[r.name] = r;
  const auto& parent = plan.at("n256_phi0.7000_r-3.00_s001");
  const auto& child = plan.at("n256_phi0.7000_r-4.00_s001");
  BOOST_TEST(child.parent == parent.name);
  BOOST_TEST(plan.at("n256_phi0.7000_r-4.50_s001").parent == child.name);
  BOOST_TEST(parent.parent.empty());

  // By hand: the parent's run, leaving its configuration at 0.80; the child from there.
  const std::string base = "sim --quiet --n 256 --phi-stop 0.85 --phi-step 0.002 --seed " +
                           std::to_string(parent.config.seed) + " --phi-init 0.7";
  o = run_jam(base + " --rate 1e-3 --relax-energy 1e-14 --write-start " + (kDir / "s.h5").string() +
              " --write-start-at 0.8 --out " + (kDir / "p.h5").string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  // The campaign's relax_energy reaches the child too: not to relax, but as the energy at which
  // its start's transient counts as settled (start_transient.hpp).
  o = run_jam(base + " --rate 1e-4 --relax 0 --relax-energy 1e-14 --read-start " +
              (kDir / "s.h5").string() + " --out " + (kDir / "k.h5").string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  // Bitwise: the same configuration, the same dynamics (the run files differ only in the
  // campaign's name and sample attributes).
  for (const char* name : {"pressure", "packing_fraction", "contacts_per_particle"}) {
    BOOST_TEST((dataset(kDir / "p.h5", name) == dataset(runs / (parent.name + ".h5"), name)), name);
    BOOST_TEST((dataset(kDir / "k.h5", name) == dataset(runs / (child.name + ".h5"), name)), name);
  }
  // The child starts at 0.80 and its start is part of its identity.
  const auto phi = dataset(runs / (child.name + ".h5"), "packing_fraction");
  BOOST_TEST(phi.front() == 0.8, boost::test_tools::tolerance(1e-12));
  {  // (one HDF5 file open at a time: the library is not thread-safe, hdf5_file.hpp)
    const auto f = jam::h5::File::open_read((runs / (child.name + ".h5")).string());
    BOOST_TEST(f.read_attribute_string("fingerprint").find(" start=") != std::string::npos);
    BOOST_TEST(f.read_attribute_int("relax") == 0);
  }

  // The averages say which rates were chained, and from where (the checks' transient rule).
  o = run_jam("stats --no-fit " + (kDir / "c").string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const auto stats = jam::h5::File::open_read((kDir / "c" / "stats.h5").string());
  std::map<double, double> chain;
  for (const auto& g : stats.list_group("ensembles")) {
    const std::string group = "ensembles/" + g;
    chain[stats.read_attribute_double("log10_rate", group)] =
        stats.read_attribute_double("chain_phi_init", group);
  }
  BOOST_TEST((chain == std::map<double, double>{{-4.5, 0.82}, {-4.0, 0.80}, {-3.0, 0.0}}));
}

BOOST_AUTO_TEST_CASE(a_damaged_start_reruns_its_parent_first) {
  const fs::path file = write_campaign("d", kChain);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet --jobs 2 " + file.string()).status == 0);
  const fs::path dir = kDir / "d";
  const auto first = run_files(dir);
  // The slowest run of sample 0 is gone, its start damaged (one flipped byte): the 1e-4 run it
  // continues from, done, must run again before it, to the start's packing only.
  const std::string child = "n256_phi0.7000_r-4.50_s000";
  const fs::path start = dir / "chain" / (child + ".start.h5");
  fs::remove(dir / "runs" / (child + ".h5"));
  {
    std::fstream s(start, std::ios::in | std::ios::out | std::ios::binary);
    s.seekp(static_cast<std::streamoff>(fs::file_size(start) / 2));
    s.put('\x5a');
  }
  const fs::path parent = dir / "runs" / "n256_phi0.7000_r-4.00_s000.h5";
  const auto parent_written = fs::last_write_time(parent);
  const fs::path log = kDir / "rerun.txt";
  const Outcome o = jam::test::run_jam_logged(log, "campaign run --jobs 2 " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  BOOST_TEST(
      slurp(log).find("n256_phi0.7000_r-4.00_s000 runs again to 0.82 only") != std::string::npos,
      slurp(log));
  BOOST_TEST(slurp(log).find("1 to run, 1 done runs again") != std::string::npos, slurp(log));
  BOOST_TEST((fs::last_write_time(parent) == parent_written));  // its run file untouched
  BOOST_TEST(!fs::exists(jam::checkpoint_path(parent.string())));
  BOOST_TEST((run_files(dir) == first));  // the child bit for bit from the start left again
}

BOOST_AUTO_TEST_CASE(a_chain_whose_starts_are_lost_leaves_them_again) {
  // A run directory restored from its run files and records alone (chain/ and starts/ lost with
  // a machine): the slowest rate of both samples is redone from the same starts, left again by
  // each faster rate in turn, each running only to its child's start.
  const fs::path file = write_campaign("l", kChain);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet --jobs 2 " + file.string()).status == 0);
  const fs::path dir = kDir / "l";
  const auto first = run_files(dir);
  std::map<std::string, std::string> records;
  for (const auto& e : fs::directory_iterator(dir / "runs")) {
    if (e.path().extension() == ".record") records[e.path().string()] = slurp(e.path());
  }
  fs::remove_all(dir / "chain");
  fs::remove_all(dir / "starts");
  for (const char* s : {"000", "001"}) {
    const std::string slowest = std::string("n256_phi0.7000_r-4.50_s") + s;
    fs::remove(dir / "runs" / (slowest + ".h5"));
    fs::remove(dir / "runs" / (slowest + ".record"));
    records.erase((dir / "runs" / (slowest + ".record")).string());
  }
  const fs::path log = kDir / "lost.txt";
  const Outcome o = jam::test::run_jam_logged(log, "campaign run --jobs 2 " + file.string());
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
  const std::string text = slurp(log);
  BOOST_TEST(text.find("2 to run, 4 done runs again") != std::string::npos, text);
  BOOST_TEST(text.find("n256_phi0.7000_r-3.00_s001 runs again to 0.8 only") != std::string::npos,
             text);
  BOOST_TEST(text.find("n256_phi0.7000_r-4.00_s001 left its start at 0.82") != std::string::npos,
             text);
  BOOST_TEST((run_files(dir) == first));
  for (const auto& [path, body] : records) BOOST_TEST(slurp(path) == body, path);
}

BOOST_AUTO_TEST_CASE(a_failed_parent_holds_its_children_back) {
  const fs::path file = write_campaign("f", kChain);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const fs::path dir = kDir / "f";
  const std::string parent = "n256_phi0.7000_r-4.00_s001", child = "n256_phi0.7000_r-4.50_s001";
  // The parent's last attempt failed; the child and its start are gone.
  fs::remove(dir / "runs" / (parent + ".h5"));
  std::ofstream(dir / "runs" / (parent + ".record")) << "status = \"failed\"\n"
                                                     << "wall_seconds = 1.0\nsteps = 0\n"
                                                     << "error = \"planted\"\n";
  fs::remove(dir / "runs" / (child + ".h5"));
  fs::remove(dir / "chain" / (child + ".start.h5"));
  const fs::path log = kDir / "held.txt";
  Outcome o = jam::test::run_jam_logged(log, "campaign run " + file.string());
  BOOST_TEST(
      slurp(log).find(child + " waits for " + parent + ", which failed") != std::string::npos,
      slurp(log));
  BOOST_TEST(!fs::exists(dir / "runs" / (child + ".h5")));
  // --retry-failed redoes the parent, then the child.
  o = run_jam("campaign run --quiet --retry-failed " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(fs::exists(dir / "runs" / (child + ".h5")));
}

BOOST_AUTO_TEST_CASE(the_plan_states_the_saving) {
  const Outcome o = run_jam("campaign plan " + write_campaign("p", kChain).string());
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(o.output.find("chained starts (chain_phi_init) save") != std::string::npos, o.output);
  // Against the same campaign unchained: the chained runs skip relaxation and start higher.
  const jam::Campaign chained = jam::parse_campaign(kChain + "output = \"x\"\n", "c.toml");
  jam::Campaign unchained = chained;
  unchained.chain_phi_init.clear();
  double a = 0, b = 0;
  for (const auto& r : jam::plan_runs(chained)) a += r.estimated_particle_steps;
  for (const auto& r : jam::plan_runs(unchained)) b += r.estimated_particle_steps;
  BOOST_TEST(a < 0.6 * b);
}

BOOST_AUTO_TEST_CASE(bad_chains_are_refused_naming_the_key) {
  auto with = [](const std::string& chain) {
    std::string text = kChain;
    return text.replace(text.find("chain_phi_init = [0, 0.80, 0.82]"), 32,
                        "chain_phi_init = " + chain);
  };
  BOOST_TEST(campaign_rejection(with("[0, 0.80, 0.82]")) == "accepted");
  BOOST_TEST(campaign_rejection(with("[0, 0.80]")) ==
             "c.toml:6: chain_phi_init: 2 values for 3 log10_rates (one per rate)");
  BOOST_TEST(campaign_rejection(with("[0.75, 0.80, 0.82]")) ==
             "c.toml:6: chain_phi_init: 0.75 at log10 rate -3: the fastest rate has no faster "
             "one to start from (give 0)");
  BOOST_TEST(campaign_rejection(with("[0, 0.82, 0.80]"))
                 .find("0.8 at log10 rate -4.5: must lie "
                       "above") != std::string::npos);
  BOOST_TEST(campaign_rejection(with("[0, 0.65, 0.82]")).find("must lie above every phi_init") !=
             std::string::npos);
  BOOST_TEST(campaign_rejection(with("[0, 0.801, 0.82]")) ==
             "c.toml:6: chain_phi_init: 0.801 at log10 rate -4: must be a multiple of phi_step "
             "(0.002), such as 0.802");
}

// Slurm array shares (--shard K/N) keep a sample's runs, so each chain, in one share.
BOOST_AUTO_TEST_CASE(a_chain_stays_in_one_share) {
  const auto plan = jam::plan_runs(jam::parse_campaign(kChain + "output = \"x\"\n", "c.toml"));
  std::map<std::string, int> share_of;
  for (int k = 1; k <= 2; ++k)
    for (const auto i : jam::shard_of(plan, k, 2)) share_of[plan[i].name] = k;
  BOOST_TEST(share_of.size() == plan.size());
  int chained = 0;
  for (const auto& r : plan) {
    if (r.parent.empty()) continue;
    ++chained;
    BOOST_TEST(share_of.at(r.name) == share_of.at(r.parent), r.name);
  }
  BOOST_TEST(chained == 4);
}

// Under MPI the chains are shared among the ranks whole: the same run files as one process.
BOOST_AUTO_TEST_CASE(mpi_chains_equal_local) {
  if (jam::find_program("mpirun").empty()) {
    BOOST_TEST_MESSAGE("mpirun not installed: skipped");
    return;
  }
  const fs::path local = write_campaign("local", kChain);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet --jobs 1 " + local.string()).status == 0);
  const fs::path distributed = write_campaign("mpi", kChain);
  const fs::path log = kDir / "mpi.txt";
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
                                         "1",
                                         distributed.string()};
  BOOST_TEST_REQUIRE(jam::test::run_logged(log, argv).status == 0, slurp(log));
  BOOST_TEST(slurp(log).find("on 2 ranks") != std::string::npos, slurp(log));
  BOOST_TEST((run_files(kDir / "mpi") == run_files(kDir / "local")));
}

BOOST_AUTO_TEST_SUITE_END()
