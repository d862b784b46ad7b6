// `jam stats DIR` on a real (tiny) campaign: stats.h5 has the documented schema and shapes,
// pooling doubles the samples, the means are the means of the stored per-sample tables,
// held exponents are reported, and a directory without finished runs is an error.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "process.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/process.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-stats-" + std::to_string(::getpid()));

int run_jam(const std::string& args, std::string* output = nullptr) {
  const auto o = jam::test::run_jam_logged(kDir / "log.txt", args);
  if (output) *output = o.output;
  return o.status;
}

struct Campaign {
  /// The shipped CI campaign, with its output in the temporary directory; `rates` in place of
  /// its log10_rates, and no jamming points, when given.
  explicit Campaign(const std::string& rates = "") {
    fs::create_directories(kDir);
    std::string text = slurp(std::string(JAM_SOURCE_DIR) + "/reference/campaigns/ci.toml");
    const std::string key = "output = \"runs/ci\"";
    text.replace(text.find(key), key.size(), "output = \"" + (kDir / "ci").string() + "\"");
    if (!rates.empty()) {
      const std::string shipped = "log10_rates = [-2.5, -3.0]";
      BOOST_TEST_REQUIRE(text.find(shipped) != std::string::npos);
      text.replace(text.find(shipped), shipped.size(), "log10_rates = " + rates);
      const std::string search = "jamming_point = true";
      BOOST_TEST_REQUIRE(text.find(search) != std::string::npos);
      text.replace(text.find(search), search.size(), "jamming_point = false");
    }
    std::ofstream(kDir / "c.toml") << text;
    BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + (kDir / "c.toml").string()) == 0);
  }
  ~Campaign() { fs::remove_all(kDir); }
};

/// The CI campaign with a third, faster rate, for the cases about the fit's file: its 2 rates
/// give no scaling fit (none is attempted). Without jamming points, which none of these cases
/// reads: their search is 90% of the CI campaign's CPU time, so the 24 runs cost a tenth of
/// its 16 (measured 0.34 s against 3.5 s; a third rate with the search cost 46% more).
struct ThreeRates : Campaign {
  ThreeRates() : Campaign("[-2.0, -2.5, -3.0]") {}
};

}  // namespace

BOOST_FIXTURE_TEST_SUITE(stats, Campaign)

BOOST_FIXTURE_TEST_CASE(schema_shapes_and_means, ThreeRates) {
  std::string out;
  BOOST_TEST_REQUIRE(run_jam("stats " + (kDir / "ci").string(), &out) == 0, out);
  BOOST_TEST(out.find("24 runs averaged") != std::string::npos, out);
  const jam::h5::File f = jam::h5::File::open_read((kDir / "ci" / "stats.h5").string());
  BOOST_TEST(f.read_attribute_string("campaign") == "ci");
  BOOST_TEST(f.read_attribute_int("runs") == 24);
  const std::string g = "ensembles/n256_phi0.7000_r-3.00";
  BOOST_TEST(f.read_attribute_int("samples", g) == 2);
  const auto phi = f.read_dataset(g + "/constant_phi/packing_fraction");
  const auto mean = f.read_dataset(g + "/constant_phi/pressure_mean");
  const auto err = f.read_dataset(g + "/constant_phi/pressure_error");
  const auto samples = f.read_dataset(g + "/constant_phi/pressure_samples");
  BOOST_TEST_REQUIRE(phi.size() > 10u);
  BOOST_TEST(mean.size() == phi.size());
  BOOST_TEST(samples.size() == 2 * phi.size());
  // Grid on multiples of phi_step inside every sample's range.
  BOOST_TEST(std::abs(phi.front() / 0.002 - std::round(phi.front() / 0.002)) < 1e-9);
  for (std::size_t k = 0; k < phi.size(); ++k) {
    const double a = samples[k], b = samples[phi.size() + k];
    BOOST_TEST(mean[k] == 0.5 * (a + b), boost::test_tools::tolerance(1e-14));
    BOOST_TEST(err[k] == std::abs(a - b) / 2.0, boost::test_tools::tolerance(1e-12));
  }
  const auto z = f.read_dataset(g + "/constant_z/contacts_per_particle");
  BOOST_TEST(f.read_dataset(g + "/constant_z/packing_fraction_mean").size() == z.size());
  BOOST_TEST(f.read_attribute_string("error_method", g + "/constant_phi").find("sigma/sqrt") !=
             std::string::npos);
  // The scan table exists; every row either fitted or says why not.
  BOOST_TEST(f.read_dataset("fit/scan/phi_j").size() == f.read_dataset("fit/scan/rate_max").size());
}

BOOST_FIXTURE_TEST_CASE(every_dataset_says_its_unit_and_refit_keeps_the_grid_spacing, ThreeRates) {
  const std::string dir = (kDir / "ci").string();
  for (const char* command : {"stats ", "stats --refit "}) {
    std::string out;
    BOOST_TEST_REQUIRE(run_jam(command + dir, &out) == 0, out);
    const jam::h5::File f = jam::h5::File::open_read((kDir / "ci" / "stats.h5").string());
    const std::string g = "ensembles/n256_phi0.7000_r-3.00";
    const auto unit = [&](const std::string& path) {
      return f.read_attribute_string("units", path);
    };
    BOOST_TEST(unit(g + "/constant_phi/packing_fraction") == "1");
    BOOST_TEST(unit(g + "/constant_phi/pressure_mean") == "k_e/d_s^D");
    BOOST_TEST(unit(g + "/constant_phi/pressure_samples") == "k_e/d_s^D");
    BOOST_TEST(unit(g + "/constant_phi/pressure_relative_error") == "1");
    BOOST_TEST(unit(g + "/constant_z/packing_fraction_error") == "1");
    BOOST_TEST(unit(g + "/constant_z/pressure_error") == "k_e/d_s^D");
    BOOST_TEST(unit("fit/scan/rate_max") == "1/t0");
    BOOST_TEST(unit("fit/scan/phi_j") == "1");
    BOOST_TEST(f.read_attribute_double("phi_step") == 0.002, command);
    BOOST_TEST(f.read_attribute_string("units").find("k_e/d_s^D") != std::string::npos);
  }
}

BOOST_FIXTURE_TEST_CASE(pooled_sizes_and_held_exponents, ThreeRates) {
  std::string out;
  BOOST_TEST_REQUIRE(
      run_jam("stats --pool-sizes --fix-paper-exponents --order 3 " + (kDir / "ci").string(),
              &out) == 0,
      out);
  const jam::h5::File f = jam::h5::File::open_read((kDir / "ci" / "stats.h5").string());
  BOOST_TEST(f.read_attribute_int("pooled_sizes") == 1);
  // A refit cannot pool what the stored averages keep apart: refused, not the largest size
  // fitted alone under --pool-sizes.
  std::string refit;
  BOOST_TEST(run_jam("stats --refit --pool-sizes " + (kDir / "ci").string(), &refit) != 0);
  BOOST_TEST(refit.find("--pool-sizes with --refit") != std::string::npos, refit);
  BOOST_TEST(f.read_attribute_int("samples", "ensembles/pooled_phi0.7000_r-3.00") == 4);
  if (f.has_dataset("fit/representative/coefficients")) {
    BOOST_TEST(f.read_attribute_string("fixed", "fit/representative") == "q, 1/(z nu)");
    BOOST_TEST(f.read_attribute_double("q", "fit/representative") == 1.12 / 3.75,
               boost::test_tools::tolerance(1e-12));
    BOOST_TEST(f.read_attribute_double("beta", "fit/representative") == 2.63,
               boost::test_tools::tolerance(1e-12));
  } else {
    BOOST_TEST(f.read_attribute_string("failure", "fit").size() > 0u);
  }
}

BOOST_FIXTURE_TEST_CASE(paper_q_held_alone, ThreeRates) {
  std::string out;
  BOOST_TEST_REQUIRE(run_jam("stats --fix-paper-q --order 3 " + (kDir / "ci").string(), &out) == 0,
                     out);
  const jam::h5::File f = jam::h5::File::open_read((kDir / "ci" / "stats.h5").string());
  if (f.has_dataset("fit/representative/coefficients")) {
    BOOST_TEST(f.read_attribute_string("fixed", "fit/representative") == "q");
    BOOST_TEST(f.read_attribute_double("q", "fit/representative") == 1.12 / 3.75,
               boost::test_tools::tolerance(1e-12));
    // 1/(z nu) was fitted: it carries a jackknife error, a held one has none.
    BOOST_TEST(f.read_attribute_double("inv_znu_error", "fit/representative") > 0.0);
  } else {
    BOOST_TEST(f.read_attribute_string("failure", "fit").size() > 0u);
  }
}

BOOST_AUTO_TEST_CASE(checks_write_json_and_junit_and_exit_with_the_verdict) {
  const std::string dir = (kDir / "ci").string();
  std::string out;
  BOOST_TEST(run_jam("check all " + dir, &out) != 0);  // before stats: an error, no verdict
  BOOST_TEST(out.find("run `jam stats") != std::string::npos, out);
  BOOST_TEST_REQUIRE(run_jam("stats " + dir) == 0);
  const int status = run_jam("check all --no-lmp " + dir, &out);
  BOOST_TEST(out.find("passed,") != std::string::npos, out);
  const std::string json = slurp(kDir / "ci" / "checks.json");
  const bool any_fail = json.find("\"status\": \"fail\"") != std::string::npos;
  const bool any_inconclusive = json.find("\"status\": \"inconclusive\"") != std::string::npos;
  BOOST_TEST(status == (any_fail ? 1 : any_inconclusive ? 3 : 0));
  BOOST_TEST(slurp(kDir / "ci" / "checks.xml").find("<testsuite name=\"jam.check.all\"") !=
             std::string::npos);
  // The plan of the campaign now reports what the phi_init check found.
  BOOST_TEST(run_jam("campaign plan " + (kDir / "c.toml").string(), &out) == 0);
  BOOST_TEST(out.find("phi_init check (N 128, rate 1e-3)") != std::string::npos, out);
  BOOST_TEST(json.find("\"largest_consistent_phi_init\"") != std::string::npos);
  BOOST_TEST(run_jam("check finite_size " + dir + " --set-a size=3 --set-b n=128", &out) != 0);
  BOOST_TEST(out.find("size=3") != std::string::npos, out);
  BOOST_TEST(run_jam("check nonsense " + dir, &out) != 0);
  // Exit statuses from the command line: 0 all pass (a margin nothing exceeds, at an alpha
  // that 2 samples against 2 can reach: their 6 splits give no p-value below 1/6), 3 only
  // inconclusive (2 samples are too few for sample pairs; at alpha 0.05 they exclude
  // nothing), 1 a failure (a baseline whose rerun sample differs in one value), 2 a usage
  // error naming the option.
  const std::string two_sets =
      " --set-a n=128,phi_init=0.7,rate=-3 --set-b n=256,phi_init=0.7,rate=-3 --margin 5";
  // Every range the data cover passes; the regions around jamming at constant Z lie below
  // where this fast campaign's Z starts, so they say there is nothing to judge (exit 3).
  const int all_covered = run_jam("check finite_size " + dir + two_sets + " --alpha 0.4", &out);
  const std::string judged = slurp(kDir / "ci" / "checks-finite_size.json");
  BOOST_TEST(judged.find("\"status\": \"fail\"") == std::string::npos, judged);
  BOOST_TEST(all_covered == (judged.find("nothing to judge") != std::string::npos ? 3 : 0), out);
  BOOST_TEST(std::count(out.begin(), out.end(), '\n') > 5);
  BOOST_TEST(run_jam("check finite_size " + dir + two_sets, &out) == 3, out);
  // The terminal's short reason says what is missing; the whole reason, in the JSON, why
  // (the splits of whole runs the permutation test had).
  BOOST_TEST(out.find(" samples") != std::string::npos, out);
  BOOST_TEST(slurp(kDir / "ci" / "checks-finite_size.json").find("splits") != std::string::npos);
  BOOST_TEST(run_jam("check sample_pairs " + dir, &out) == 3, out);
  {
    // The campaign file's [regions] place the regions when no option does; an option wins.
    const fs::path stored = kDir / "ci" / "campaign.toml";
    const std::string text = slurp(stored);
    std::ofstream(stored) << text << "\n[regions]\nphi_j = 0.845\n";
    run_jam("check finite_size " + dir, &out);
    const std::string judged = slurp(kDir / "ci" / "checks-finite_size.json");
    BOOST_TEST(judged.find("relative to phi_J 0.84500") != std::string::npos, judged);
    run_jam("check finite_size " + dir + " --phi-j 0.84", &out);
    BOOST_TEST(slurp(kDir / "ci" / "checks-finite_size.json").find("relative to phi_J 0.84000") !=
               std::string::npos);
    std::ofstream(stored) << text;
  }
  const fs::path changed = kDir / "changed";
  fs::create_directories(changed);
  fs::copy_file(kDir / "ci" / "stats.h5", changed / "stats.h5");
  BOOST_TEST_REQUIRE(
      jam::run_program({"/usr/bin/python3", "-c",
                        "import h5py, sys\n"
                        "f = h5py.File(sys.argv[1], 'r+')\n"
                        "d = f['ensembles/n128_phi0.7000_r-3.00/constant_phi/pressure_samples']\n"
                        "d[1, 5] = d[1, 5] * 1.01\n",
                        (changed / "stats.h5").string()}) == 0);
  // The edit breaks the file's checksum: refused, not judged.
  BOOST_TEST(run_jam("check regression " + dir + " --against " + changed.string(), &out) == 2, out);
  BOOST_TEST(out.find("changed since `jam stats` wrote it") != std::string::npos, out);
  // Without a checksum (a file written before stats.h5 carried one) it is judged: the changed
  // sample is caught.
  BOOST_TEST_REQUIRE(jam::run_program({"/usr/bin/python3", "-c",
                                       "import h5py, sys\n"
                                       "del h5py.File(sys.argv[1], 'r+').attrs['checksum']\n",
                                       (changed / "stats.h5").string()}) == 0);
  BOOST_TEST(run_jam("check regression " + dir + " --against " + changed.string(), &out) == 1, out);
  for (const char* bad : {"0", "-0.1", "nan", "inf"}) {
    BOOST_TEST(run_jam("check finite_size " + dir + " --margin " + bad, &out) == 2, out);
    BOOST_TEST(out.find("--margin") != std::string::npos, out);
    BOOST_TEST(std::count(out.begin(), out.end(), '\n') == 1, out);
  }
  // Regression of the campaign against itself: every sample a bitwise-identical rerun. Its
  // verdicts go to checks-regression.*, leaving the full set in checks.* untouched.
  // (No new samples: that half is inconclusive, so the exit status is 3.)
  BOOST_TEST(run_jam("check regression " + dir + " --against " + dir, &out) == 3, out);
  BOOST_TEST(out.find("rerun samples identical") != std::string::npos, out);
  BOOST_TEST(fs::exists(kDir / "ci" / "checks-regression.json"));
  BOOST_TEST(slurp(kDir / "ci" / "checks.json") == json);
  BOOST_TEST(run_jam("check regression " + dir, &out) != 0);
  BOOST_TEST(out.find("--against") != std::string::npos, out);
}

// The CI campaign's 2 rates cannot give a scaling fit: none is attempted. One line says why,
// naming the rates; stats.h5 holds no fit (as with --no-fit), and no scan line follows.
BOOST_AUTO_TEST_CASE(two_rates_attempt_no_fit_and_say_why) {
  std::string out;
  BOOST_TEST_REQUIRE(run_jam("stats " + (kDir / "ci").string(), &out) == 0, out);
  BOOST_TEST(out.find("fit failed") == std::string::npos, out);
  BOOST_TEST(out.find("scaling fit at constant") == std::string::npos, out);
  const std::string line =
      "scaling fit: none attempted: fewer than 3 rates (the fitted ensembles, phi_init 0.7 and "
      "N 256, have 2: 1e-2.5, 1e-3); a scaling fit needs at least 3 (with 2, phi_J and q trade "
      "off)\n";
  BOOST_TEST(out.find(line) != std::string::npos, out);
  BOOST_TEST(out.find("scaling fit:", out.find(line) + 1) == std::string::npos, out);
  const jam::h5::File f = jam::h5::File::open_read((kDir / "ci" / "stats.h5").string());
  BOOST_TEST(f.read_attribute_string("units",
                                     "ensembles/n256_phi0.7000_r-3.00/jamming/"
                                     "packing_fraction_samples") == "1");
  BOOST_TEST(!f.has_dataset("fit"));
  BOOST_TEST(!f.has_dataset("fit_z"));
  // A refit of the stored averages decides the same.
  BOOST_TEST_REQUIRE(run_jam("stats --refit " + (kDir / "ci").string(), &out) == 0, out);
  BOOST_TEST(out.find(line) != std::string::npos, out);
}

namespace {

std::size_t lammps_verdicts(const fs::path& checks_json) {
  const std::string json = slurp(checks_json);
  std::size_t n = 0;
  for (auto at = json.find("\"check\": \"lammps\""); at != std::string::npos;
       at = json.find("\"check\": \"lammps\"", at + 1))
    ++n;
  return n;
}

}  // namespace

// The LAMMPS self-checks test jam, not the campaign: `check all` judges them only when asked
// (--with-lammps, [question] checks naming lammps, or `check lammps`), and says in one line how
// to ask when it leaves them out.
BOOST_AUTO_TEST_CASE(lammps_self_checks_only_when_asked) {
  const std::string dir = (kDir / "ci").string();
  const std::string reference =
      " --no-lmp --reference-dir " + std::string(JAM_SOURCE_DIR) + "/reference ";
  const std::string note = "lammps: the LAMMPS self-checks were not run";
  BOOST_TEST_REQUIRE(run_jam("stats " + dir) == 0);
  std::string out;
  run_jam("check all" + reference + dir, &out);
  BOOST_TEST(lammps_verdicts(kDir / "ci" / "checks.json") == 0u);
  const auto at = out.find(note);
  BOOST_TEST_REQUIRE(at != std::string::npos, out);
  BOOST_TEST(out.find(note, at + 1) == std::string::npos, out);
  BOOST_TEST(out.find("`jam check lammps DIR`, `--with-lammps`") != std::string::npos, out);
  // Asked on the command line: every stored self-check, and the record says so.
  run_jam("check all --with-lammps" + reference + dir, &out);
  BOOST_TEST(lammps_verdicts(kDir / "ci" / "checks.json") == 18u);
  BOOST_TEST(out.find(note) == std::string::npos, out);
  BOOST_TEST(slurp(kDir / "ci" / "checks.json").find("\"with_lammps\": true") != std::string::npos);
  // Asked by the campaign's question.
  const fs::path stored = kDir / "ci" / "campaign.toml";
  const std::string text = slurp(stored);
  std::ofstream(stored) << text << "\n[question]\nchecks = [\"finite_size\", \"lammps\"]\n";
  run_jam("check all" + reference + dir, &out);
  BOOST_TEST(lammps_verdicts(kDir / "ci" / "checks.json") == 18u);
  BOOST_TEST(out.find(note) == std::string::npos, out);
  std::ofstream(stored) << text;
  // By name, as ever.
  BOOST_TEST(run_jam("check lammps" + reference + dir, &out) == 0, out);
  BOOST_TEST(lammps_verdicts(kDir / "ci" / "checks-lammps.json") == 18u);
}

BOOST_AUTO_TEST_CASE(no_finished_runs_is_an_error) {
  for (const auto& e : fs::directory_iterator(kDir / "ci" / "runs")) fs::remove(e.path());
  fs::remove(kDir / "ci" / "stats.h5");
  std::string out;
  BOOST_TEST(run_jam("stats " + (kDir / "ci").string(), &out) != 0);
  BOOST_TEST(out.find("no finished runs") != std::string::npos, out);
  BOOST_TEST(!fs::exists(kDir / "ci" / "stats.h5"));
}

BOOST_AUTO_TEST_SUITE_END()
