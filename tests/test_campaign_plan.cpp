// `jam campaign plan` on what a design can decide (design/plan_decidability.hpp), through the
// executable: the stored 2D variance model says that two samples of N = 256 against N = 1024
// cannot decide the pressure at constant phi, and warns with the samples needed; with 400
// samples every comparison decides; a --scatter-from that is missing is one line and no plan;
// --pilot K runs the campaign's first K samples in <output>-pilot-K and plans from them; the
// phi_init findings of a judged directory are printed; data of one size hold the N exponent.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <utility>
#include <vector>

#include "process.hpp"
#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("plan");

jam::test::Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

fs::path write_campaign(const std::string& name, const std::string& body) {
  fs::create_directories(kDir);
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << "name = \"" << name << "\"\n"
                      << body << "output = \"" << (kDir / name).string() << "\"\n";
  return file;
}

// A coefficient as the plan prints it ("{:+.2f}").
std::string fmt_two(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.2f", x);
  return buf;
}

const std::string kSizes =
    "dim = 2\nsizes = [256, 1024]\nphi_init = [0.4]\nlog10_rates = [-4.0, -5.0]\n"
    "phi_stop = 0.86\nseed = 1\n";

}  // namespace

BOOST_AUTO_TEST_CASE(few_samples_warn_and_many_decide) {
  const auto few =
      run_jam("campaign plan " + write_campaign("few", kSizes + "samples = 2\n").string());
  BOOST_TEST(few.status == 0, few.output);
  BOOST_TEST(few.output.find("what it can decide") != std::string::npos, few.output);
  // N = 256 near jamming scatters by 10-30% per run (reduced-2d): two samples cannot exclude 10%.
  BOOST_TEST(
      std::regex_search(few.output, std::regex("warning: finite_size, constant phi: [0-1] of 2 "
                                               "comparisons decide with 2 samples; the other [1-2] "
                                               "need up to [0-9]+ samples per set")),
      few.output);
  const auto many =
      run_jam("campaign plan " + write_campaign("many", kSizes + "samples = 400\n").string());
  BOOST_TEST(many.status == 0, many.output);
  BOOST_TEST(many.output.find("finite_size, constant phi: all 2 comparisons decide with 400") !=
                 std::string::npos,
             many.output);
  BOOST_TEST(many.output.find("warning") == std::string::npos, many.output);
}

BOOST_AUTO_TEST_CASE(a_missing_model_is_one_line_and_no_plan) {
  const auto o = run_jam("campaign plan " + write_campaign("m", kSizes + "samples = 2\n").string() +
                         " --scatter-from " + (kDir / "nothing").string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(o.output.find("--scatter-from") != std::string::npos, o.output);
  BOOST_TEST(o.output.find("particle-steps") == std::string::npos, o.output);
}

BOOST_AUTO_TEST_CASE(a_pilot_runs_the_first_samples_and_plans_from_them) {
  const fs::path file = write_campaign(
      "p",
      "dim = 2\nsizes = [64, 128]\nphi_init = [0.70]\nlog10_rates = [-2.5, -3.0]\nsamples = 20\n"
      "phi_stop = 0.86\nphi_step = 0.002\ndt = 0.02\nseed = 5\n");
  const auto o = run_jam("campaign plan " + file.string() + " --pilot 3");
  BOOST_TEST(o.status == 0, o.output);
  const fs::path pilot = kDir / "p-pilot-3";
  BOOST_TEST(fs::exists(pilot / "checks.json"));
  BOOST_TEST(o.output.find((pilot / "checks.json").string()) != std::string::npos, o.output);
  // Its runs are the campaign's samples 0-2: the same names, and only those.
  int runs = 0;
  for (const auto& e : fs::directory_iterator(pilot / "runs")) {
    if (e.path().extension() != ".h5") continue;
    ++runs;
    BOOST_TEST(std::regex_search(e.path().filename().string(), std::regex("_s00[0-2]\\.h5$")),
               e.path());
  }
  BOOST_TEST(runs == 2 * 2 * 3);
  // The campaign itself is untouched.
  BOOST_TEST(!fs::exists(kDir / "p"));
}

// Once runs of the campaign have finished, the plan states its own error on them: their
// recorded CPU seconds against what it gives them, in all and per rate. A campaign with nothing
// run says nothing of the kind.
BOOST_AUTO_TEST_CASE(the_plan_measures_itself_on_finished_runs) {
  const fs::path file = write_campaign(
      "f",
      "dim = 2\nsizes = [64]\nphi_init = [0.70]\nlog10_rates = [-2.5, -3.0]\nsamples = 2\n"
      "phi_stop = 0.86\nphi_step = 0.002\nseed = 5\n");
  auto o = run_jam("campaign plan " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(o.output.find("measured so far") == std::string::npos, o.output);
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  o = run_jam("campaign plan " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  std::smatch m;
  const bool found = std::regex_search(
      o.output, m,
      std::regex("measured so far: 4 finished runs took [0-9.e+-]+ core-hours, planned "
                 "[0-9.e+-]+ for them \\(measured / planned ([0-9.]+); by rate 1e-3 [0-9.]+, "
                 "1e-2.5 [0-9.]+\\)"));
  BOOST_TEST_REQUIRE(found, o.output);
  BOOST_TEST(std::stod(m[1]) > 0.0);
}

BOOST_AUTO_TEST_CASE(the_phi_init_findings_in_the_directory_are_printed) {
  // A phi_init verdict in DIR/checks.json that found a higher start consistent with the lowest:
  // the plan says which start, at which size and rate, and the compression time it saves.
  const fs::path file = write_campaign("found", kSizes + "samples = 2\n");
  fs::create_directories(kDir / "found");
  std::ofstream(kDir / "found" / "checks.json")
      << R"({"schema_version": 2, "verdicts": [{"check": "phi_init", "case": "n256 rate 1e-4",)"
      << R"( "status": "pass",)"
      << R"( "values": {"n": 256, "log10_rate": -4, "largest_consistent_phi_init": 0.6,)"
      << R"( "lowest_phi_init": 0.4, "compression_time_saved": 0.37}}]})";
  const auto o = run_jam("campaign plan " + file.string());
  BOOST_TEST(o.status == 0, o.output);
  BOOST_TEST(o.output.find("phi_init check (N 256, rate 1e-4): starting at phi_init 0.6 instead "
                           "of 0.4 gives the same pressures and saves 37% of the compression "
                           "time") != std::string::npos,
             o.output);
  // Nothing is said of a directory without verdicts.
  const auto none =
      run_jam("campaign plan " + write_campaign("none", kSizes + "samples = 2\n").string());
  BOOST_TEST(none.output.find("phi_init check (") == std::string::npos, none.output);
}

// A pilot of one size cannot tell how the scatter scales with N: the model holds the
// self-averaging exponent (s^2 ~ 1/N) and says so, so that N = 4096 and 8192 are planned from
// N = 256's scatter divided by 4 and 5.7 (they decide with 10 samples), not from N = 256's own
// (they would not); data of two sizes fit the exponent (planted at -0.5 here).
BOOST_AUTO_TEST_CASE(one_size_in_the_data_holds_the_n_exponent) {
  auto pilot = [](const std::string& name, const std::vector<std::pair<int, double>>& scatter) {
    const fs::path dir = kDir / name;
    fs::create_directories(dir);
    std::ofstream out(dir / "checks.json");
    const char* sep = "[";
    for (const auto& [n, s] : scatter) {
      for (const char* rate : {"-4", "-5"}) {
        out << sep << "{\"check\": \"finite_size\", \"case\": \"pilot\", "
            << "\"status\": \"inconclusive\", \"values\": {\"log10_rate\": " << rate
            << ", \"n\": " << n << ", \"scatter_a\": " << s << ", \"scatter_b\": " << s
            << ", \"samples_a\": 10, \"samples_b\": 10}}";
        sep = ", ";
      }
    }
    out << "]\n";
    return dir.string();
  };
  const std::string design = write_campaign("large",
                                            "dim = 2\nsizes = [4096, 8192]\nphi_init = [0.4]\n"
                                            "log10_rates = [-4.0, -5.0]\nphi_stop = 0.86\n"
                                            "seed = 1\nsamples = 10\n")
                                 .string();
  const auto one =
      run_jam("campaign plan " + design + " --scatter-from " + pilot("one-size", {{256, 0.2}}));
  BOOST_TEST(one.status == 0, one.output);
  BOOST_TEST(one.output.find("-1.00 ln N (held: one size in the data)") != std::string::npos,
             one.output);
  BOOST_TEST(one.output.find("finite_size, constant phi: all 2 comparisons decide with 10") !=
                 std::string::npos,
             one.output);
  const auto two = run_jam("campaign plan " + design + " --scatter-from " +
                           pilot("two-sizes", {{256, 0.2}, {1024, 0.2 / std::sqrt(2.0)}}));
  BOOST_TEST(two.status == 0, two.output);
  BOOST_TEST(two.output.find("-0.50 ln N ") != std::string::npos, two.output);
  BOOST_TEST(two.output.find("held") == std::string::npos, two.output);
}

// What "decides" refers to: the range the campaign file asks about ([question]), else, with
// fewer than 3 rates (no scaling fit), the whole compression, said as such.
BOOST_AUTO_TEST_CASE(the_plan_says_which_range_its_verdicts_judge) {
  const auto whole =
      run_jam("campaign plan " + write_campaign("whole", kSizes + "samples = 2\n").string());
  BOOST_TEST(whole.status == 0, whole.output);
  BOOST_TEST(whole.output.find("the verdicts judge the whole compression, phi 0.4 to 0.86: 2 "
                               "rates give no scaling fit and the campaign file states no range "
                               "([question] phi_min, phi_max)") != std::string::npos,
             whole.output);
  const fs::path file = write_campaign("asked", kSizes + "samples = 2\n");
  std::ofstream(file, std::ios::app) << "[question]\nphi_min = 0.83\nphi_max = 0.85\n";
  const auto asked = run_jam("campaign plan " + file.string());
  BOOST_TEST(asked.status == 0, asked.output);
  BOOST_TEST(asked.output.find("the verdicts judge the range asked, phi in [0.83, 0.85] "
                               "([question] phi_min, phi_max)") != std::string::npos,
             asked.output);
  // The stored model's source judged no range asked: said beside it.
  BOOST_TEST(asked.output.find("it judged no range asked") != std::string::npos, asked.output);
}

// A pilot of two sizes at one rate gives two points for two coefficients: the model passes
// through them (said), never left at zero, which would predict s = 1 and thousands of samples
// needed. A kind of comparison the data hold no verdict of (constant Z here) is said, not
// planned from a zero model.
BOOST_AUTO_TEST_CASE(a_two_point_pilot_is_fitted_exactly_and_a_missing_kind_is_said) {
  const fs::path dir = kDir / "two-point";
  fs::create_directories(dir);
  std::ofstream(dir / "checks.json")
      << "[{\"check\": \"finite_size\", \"case\": \"pilot\", \"status\": \"pass\", "
         "\"values\": {\"log10_rate\": -3, \"n_a\": 128, \"n_b\": 512, \"constant_z\": 0, "
         "\"scatter_a\": 0.04, \"scatter_b\": 0.027, \"samples_a\": 20, \"samples_b\": 20}}]\n";
  const std::string design = write_campaign("two-point-design",
                                            "dim = 2\nsizes = [128, 512]\nphi_init = [0.8]\n"
                                            "log10_rates = [-3.0]\nphi_stop = 0.87\nseed = 1\n"
                                            "samples = 20\n")
                                 .string();
  const auto r = run_jam("campaign plan " + design + " --scatter-from " + dir.string());
  BOOST_TEST(r.status == 0, r.output);
  // ln s^2 through (ln 128, ln 0.04^2) and (ln 512, ln 0.027^2): slope 2 ln(0.027/0.04)/ln 4.
  const double slope = 2 * std::log(0.027 / 0.04) / std::log(4.0);
  BOOST_TEST(r.output.find(fmt_two(slope) + " ln N ") != std::string::npos, r.output);
  BOOST_TEST(
      r.output.find("through its points exactly: no residual to estimate") != std::string::npos,
      r.output);
  // s_a = 0.04, s_b = 0.027 at 20 samples: sigma_D 0.011, well under 0.1 / (1.645 + 1.28).
  BOOST_TEST(r.output.find("finite_size, constant phi: all 1 comparisons decide with 20") !=
                 std::string::npos,
             r.output);
  BOOST_TEST(
      r.output.find("finite_size, constant Z: no verdict of its kind in") != std::string::npos,
      r.output);
}

// The price comes from stored measurements (reference/throughput.toml), then from the
// campaign's own finished runs: the same plan, word for word, on every invocation for the same
// runs, however busy the machine (a probe per plan moved one design's cost by 45%). The probe
// only when asked, with its spread.
BOOST_AUTO_TEST_CASE(the_plan_is_the_same_on_every_invocation) {
  const fs::path file = write_campaign(
      "same",
      "dim = 2\nsizes = [64, 128]\nphi_init = [0.70]\nlog10_rates = [-2.5]\nsamples = 2\n"
      "phi_stop = 0.80\nphi_step = 0.002\nseed = 7\n");
  auto plan = [&](const std::string& more = "") {
    const auto o = run_jam("campaign plan " + file.string() + more);
    BOOST_TEST(o.status == 0, o.output);
    return o.output;
  };
  const std::string first = plan();
  BOOST_TEST(plan() == first);
  for (const char* n : {"N =      64:", "N =     128:"}) {
    const auto at = first.find(n);
    BOOST_TEST_REQUIRE(at != std::string::npos, first);
    BOOST_TEST(
        first.substr(at, first.find('\n', at) - at).find("(stored, reference/throughput.toml)") !=
            std::string::npos,
        first);
  }
  // Once runs have finished, their recorded CPU seconds price their sizes.
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + file.string()).status == 0);
  const std::string measured = plan();
  BOOST_TEST(plan() == measured);
  BOOST_TEST(measured.find("(this campaign's 2 finished runs, their recorded CPU seconds)") !=
                 std::string::npos,
             measured);
  BOOST_TEST(measured.find("stored, reference") == std::string::npos, measured);
  // The probe, asked for, says its spread; the sizes finished runs measured keep their price.
  fs::remove_all(kDir / "same");
  const std::string probed = plan(" --probe");
  BOOST_TEST(std::regex_search(probed, std::regex("N =      64: .*\\(probe of this machine, 3 "
                                                  "repeats: min [0-9.e+]+, median [0-9.e+]+, "
                                                  "max [0-9.e+]+\\)")),
             probed);
}
