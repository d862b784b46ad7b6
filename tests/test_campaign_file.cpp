// Campaign files: every kind of bad input is rejected with the file, line and key; seeds
// derive from (base seed, size, phi_init, sample) only; the plan is complete and ordered.
#include <fmt/format.h>
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_file.hpp"
#include "campaign/run_plan.hpp"
#include "campaign/throughput.hpp"

using namespace jam;

namespace {

const std::string kGood = R"(name = "t"
dim = 2
sizes = [64, 128]
phi_init = [0.7, 0.8]
log10_rates = [-3, -3.5]
samples = 3
phi_stop = 0.86
seed = 5
output = "out"
)";

std::string rejection(const std::string& text) {
  try {
    parse_campaign(text, "c.toml");
  } catch (const CampaignError& e) {
    return e.what();
  }
  return "accepted";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  BOOST_TEST_REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

BOOST_AUTO_TEST_CASE(good_file_parses) {
  const Campaign c = parse_campaign(kGood, "c.toml");
  BOOST_TEST(c.name == "t");
  BOOST_TEST(c.sizes.size() == 2u);
  BOOST_TEST(c.log10_rates[1] == -3.5);
  BOOST_TEST(c.run.dt == 0.1);  // default (Heun)
  BOOST_TEST(c.samples == 3);
}

BOOST_AUTO_TEST_CASE(errors_name_file_line_and_key) {
  BOOST_TEST(rejection(kGood + "colour = 3\n") == "c.toml:10: colour: unknown key");
  BOOST_TEST(rejection(replace(kGood, "samples = 3", "samples = \"3\"")) ==
             "c.toml:6: samples: must be an integer");
  BOOST_TEST(rejection(replace(kGood, "dim = 2", "dim = 4")) ==
             "c.toml:2: dim: 4 (must be 2 or 3)");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, 127]")) ==
             "c.toml:3: sizes: 127 (each must be even and >= 2)");
  BOOST_TEST(rejection(replace(kGood, "phi_init = [0.7, 0.8]", "phi_init = [0.7, 0.9]")) ==
             "c.toml:4: phi_init: 0.9 (each must be in (0, phi_stop = 0.86))");
  BOOST_TEST(rejection(replace(kGood, "log10_rates = [-3, -3.5]", "log10_rates = [-3, 1]")) ==
             "c.toml:5: log10_rates: 1 (must be in [-12, 0])");
  BOOST_TEST(rejection(replace(kGood, "seed = 5\n", "")) == "c.toml: seed: missing (required)");
  BOOST_TEST(rejection(kGood + "dt = -0.01\n") ==
             "c.toml:10: dt: -0.01: must be a finite number > 0");
  BOOST_TEST(rejection(kGood + "integrator = \"rk4\"\n") ==
             "c.toml:10: integrator: rk4: overdamped dynamics takes euler, heun or chebyshev");
  BOOST_TEST(rejection(kGood + "dt = nan\n") == "c.toml:10: dt: must be finite");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, 64]")) ==
             "c.toml:3: sizes: repeated value");
  BOOST_TEST(rejection(replace(kGood, "samples = 3", "samples = 0")) ==
             "c.toml:6: samples: 0 (must be in [1, 10^6])");
  // Infinite, negative, out-of-range and wrongly typed values.
  BOOST_TEST(rejection(kGood + "dt = inf\n") == "c.toml:10: dt: must be finite");
  BOOST_TEST(rejection(kGood + "skin = -inf\n") == "c.toml:10: skin: must be finite");
  BOOST_TEST(rejection(replace(kGood, "phi_stop = 0.86", "phi_stop = nan")) ==
             "c.toml:7: phi_stop: must be finite");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, -128]")) ==
             "c.toml:3: sizes: -128 (each must be even and >= 2)");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, 4294967296]")) ==
             "c.toml:3: sizes: 4294967296 (at most 2^31)");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, \"x\"]")) ==
             "c.toml:3: sizes: must be a non-empty array of integers");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, 128.0]")) ==
             "c.toml:3: sizes: must be a non-empty array of integers");
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = 64")) ==
             "c.toml:3: sizes: must be a non-empty array of integers");
  BOOST_TEST(rejection(replace(kGood, "phi_init = [0.7, 0.8]", "phi_init = [0.7, inf]")) ==
             "c.toml:4: phi_init: values must be finite");
  BOOST_TEST(rejection(replace(kGood, "phi_init = [0.7, 0.8]", "phi_init = [-0.7]")) ==
             "c.toml:4: phi_init: -0.7 (each must be in (0, phi_stop = 0.86))");
  BOOST_TEST(rejection(replace(kGood, "dim = 2", "dim = 4294967298")) ==
             "c.toml:2: dim: 4294967298 (must be 2 or 3)");  // not truncated to 2
  BOOST_TEST(rejection(replace(kGood, "dim = 2", "dim = 2.0")) ==
             "c.toml:2: dim: must be an integer");
  BOOST_TEST(rejection(replace(kGood, "samples = 3", "samples = -3")) ==
             "c.toml:6: samples: -3 (must be in [1, 10^6])");
  BOOST_TEST(rejection(replace(kGood, "seed = 5", "seed = -5")) ==
             "c.toml:8: seed: -5 (must be >= 0)");
  BOOST_TEST(rejection(replace(kGood, "name = \"t\"", "name = 1")) ==
             "c.toml:1: name: must be a string");
  BOOST_TEST(rejection(kGood + "relax = 1\n") == "c.toml:10: relax: must be true or false");
  BOOST_TEST(rejection(kGood + "diameter_ratio = 2.5\n") ==
             "c.toml:10: diameter_ratio: 2.5: must be in [1, 2]");
  BOOST_TEST(rejection(kGood + "[extra]\nx = 1\n") == "c.toml:10: extra: unknown key");
  BOOST_TEST(rejection(replace(kGood, "output = \"out\"\n", "")) ==
             "c.toml: output: missing (required)");
  BOOST_TEST(rejection("").rfind("c.toml: name: missing", 0) == 0u);
  // Integers beyond 2^53, which no double holds exactly, where numbers are read (toml++ gives
  // no double for them; found by fuzzing): rounded, then judged like any number.
  BOOST_TEST(rejection(kGood + "dt = -9007199254740993\n") ==
             "c.toml:10: dt: -9.0072e+15: must be a finite number > 0");
  BOOST_TEST(rejection(replace(kGood, "phi_init = [0.7, 0.8]", "phi_init = [9007199254740993]")) ==
             "c.toml:4: phi_init: 9.0072e+15 (each must be in (0, phi_stop = 0.86))");
  BOOST_TEST(rejection(kGood + "[margins]\nfinite_size = -9007199254740993\n") ==
             "c.toml:10: margins: finite_size = -9007199254740992: must be > 0");
  // [regions]: where the regions around jamming lie (checks/regions.hpp).
  BOOST_TEST(parse_campaign(kGood + "[regions]\nphi_j = 0.84086\nfar = 0.01\n", "c.toml")
                 .regions.at("phi_j") == 0.84086);
  BOOST_TEST(rejection(kGood + "[regions]\nphi = 0.84\n") ==
             "c.toml:10: regions: phi: unknown key");
  BOOST_TEST(rejection(kGood + "[regions]\nphi_j = 1.2\n").find("phi_j = 1.2: must be a packing") !=
             std::string::npos);
  BOOST_TEST(rejection(kGood + "[regions]\nnear = 0.02\nfar = 0.01\n")
                 .find("far = 0.01: must exceed near = 0.02") != std::string::npos);
  // Its own output is no other campaign (planning it would read itself without end).
  BOOST_TEST(rejection(kGood + "chain_phi_init = [0, 0.82]\nchain_starts_from = \"./out\"\n")
                 .find("is this campaign's own output") != std::string::npos);
  // chain_starts_from names the packings it reads at: without chain_phi_init it is refused.
  BOOST_TEST(rejection(kGood + "chain_starts_from = \"runs/x\"\n")
                 .find("chain_starts_from: 'runs/x': needs chain_phi_init") != std::string::npos);
  // Non-ASCII text (the TOML parser has undefined behaviour on some of it) and control bytes.
  BOOST_TEST(rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64\xcd\xbd, 128]")) ==
             "c.toml:3: byte 0xcd: campaign files are plain ASCII text");
  BOOST_TEST(rejection(kGood + "# \xc2\xa7\n") ==
             "c.toml:10: byte 0xc2: campaign files are plain ASCII text");
  BOOST_TEST(rejection(std::string("name = \"t\"\0\n", 11)) ==
             "c.toml:1: byte 0x00: campaign files are plain ASCII text");
  // Malformed table headers (toml++ 3.3.0 asserts on these in debug builds; found by fuzzing).
  BOOST_TEST(rejection(kGood + "[ # x\n").rfind("c.toml:10: Error while parsing key", 0) == 0u);
  BOOST_TEST(rejection(kGood + "[[ =\n").rfind("c.toml:10: Error while parsing key", 0) == 0u);
  // Syntax errors carry the line of the parser.
  BOOST_TEST(rejection(kGood + "dt = = 3\n").rfind("c.toml:10: ", 0) == 0u);
}

BOOST_AUTO_TEST_CASE(seeds_do_not_depend_on_rate_or_sample_count) {
  const Campaign a = parse_campaign(kGood, "a.toml");
  const Campaign b = parse_campaign(
      replace(replace(kGood, "samples = 3", "samples = 5"), "[-3, -3.5]", "[-2, -3, -3.5]"),
      "b.toml");
  std::map<std::string, std::uint64_t> seeds_a;
  std::set<std::uint64_t> distinct;
  for (const auto& r : plan_runs(a)) {
    seeds_a[r.name] = r.config.seed;
    distinct.insert(r.config.seed);
    // Same (size, phi_init, sample) at another rate: the same start.
    BOOST_TEST(r.config.seed == derive_seed(5, r.n, r.phi_init, r.sample));
  }
  BOOST_TEST(distinct.size() == 2u * 2u * 3u);  // one seed per (size, phi_init, sample)
  for (const auto& r : plan_runs(b)) {
    if (seeds_a.count(r.name)) BOOST_TEST(seeds_a[r.name] == r.config.seed);  // unchanged
  }
}

BOOST_AUTO_TEST_CASE(first_sample_reruns_part_of_a_campaign_or_adds_samples) {
  std::map<std::string, std::uint64_t> whole;
  for (const auto& r : plan_runs(parse_campaign(kGood, "a.toml"))) whole[r.name] = r.config.seed;
  // Samples 2, 3, 4: sample 2 is the whole campaign's run (same name, same seed), 3 and 4
  // are new.
  const Campaign part = parse_campaign(kGood + "first_sample = 2\n", "b.toml");
  BOOST_TEST(part.first_sample == 2);
  std::set<std::int64_t> numbers;
  for (const auto& r : plan_runs(part)) {
    numbers.insert(r.sample);
    if (r.sample == 2) {
      BOOST_TEST_REQUIRE(whole.count(r.name) == 1u, r.name);
      BOOST_TEST(whole[r.name] == r.config.seed);
    } else {
      BOOST_TEST(whole.count(r.name) == 0u, r.name);
    }
  }
  BOOST_TEST((numbers == std::set<std::int64_t>{2, 3, 4}));
  BOOST_TEST(rejection(kGood + "first_sample = -1\n") ==
             "c.toml:10: first_sample: -1 (must be in [0, 10^6])");
}

BOOST_AUTO_TEST_CASE(plan_is_complete_and_longest_first) {
  const Campaign c = parse_campaign(kGood, "c.toml");
  const auto plan = plan_runs(c);
  BOOST_TEST(plan.size() == 2u * 2u * 2u * 3u);
  for (std::size_t k = 1; k < plan.size(); ++k) {
    BOOST_TEST(plan[k - 1].estimated_particle_steps >= plan[k].estimated_particle_steps);
  }
  // The longest is the largest size, lowest phi_init, slowest rate: its compression alone is
  // N ln(phi_stop/phi_init) / (D rate dt) steps of two force evaluations (Heun, the default).
  BOOST_TEST(plan.front().n == 128);
  BOOST_TEST(plan.front().phi_init == 0.7);
  BOOST_TEST(plan.front().log10_rate == -3.5);
  const double compression = 2 * 128 * std::log(0.86 / 0.7) / (2 * std::pow(10.0, -3.5) * 0.1);
  BOOST_TEST(plan.front().estimated_particle_steps > compression);
  BOOST_TEST(plan.front().config.out == "out/runs/n128_phi0.7000_r-3.50_s000.h5");
}

// The jamming point's search is costed: measured, it costs the compression itself 10-40 times
// over at N = 1024 ... 16384 (run_plan.cpp). With jamming_point on, every run's estimate grows
// by the minimizations of its bisection (log2 of the saved points, then of phi_step / 1e-5),
// each ~ N^1.5 particle-steps; the search, not the compression, then sets the largest run.
BOOST_AUTO_TEST_CASE(plan_costs_the_jamming_point_search) {
  const auto without = plan_runs(parse_campaign(kGood, "c.toml"));
  const auto with = plan_runs(parse_campaign(kGood + "jamming_point = true\n", "c.toml"));
  BOOST_TEST_REQUIRE(with.size() == without.size());
  std::map<std::string, double> extra;
  for (const auto& r : with) extra[r.name] = r.estimated_particle_steps;
  for (const auto& r : without) extra[r.name] -= r.estimated_particle_steps;
  for (const auto& r : with) {
    // phi_step 0.001 (default) over phi_init -> 0.86: ceil(log2(points)) + ceil(log2(100)).
    const double points = (0.86 - r.phi_init) / 0.001;
    const double minimizations = std::ceil(std::log2(points)) + 7;
    const double n = static_cast<double>(r.n);
    BOOST_TEST(extra[r.name] == minimizations * 2.5e4 * std::sqrt(n / 1024) * n,
               boost::test_tools::tolerance(1e-12));
  }
}

// The root-mean-square error norm is charged as the largest component's at ten times its
// tolerance, kRmsEvaluationGain fewer (measured: integrator_cost.hpp, test_integrator_cost);
// so "auto", a tenth with rms, plans cheaper than auto with max, not the 1.8x dearer the
// tolerance alone would say.
BOOST_AUTO_TEST_CASE(plan_charges_the_rms_norm_as_measured) {
  const auto with_max = plan_runs(parse_campaign(kGood + "integrator = \"chebyshev\"\n", "c.toml"));
  const auto with_rms = plan_runs(
      parse_campaign(kGood + "integrator = \"chebyshev\"\nerror_norm = \"rms\"\n", "c.toml"));
  BOOST_TEST_REQUIRE(with_rms.size() == with_max.size());
  double a = 0, b = 0;
  for (const auto& r : with_max) a += r.estimated_particle_steps;
  for (const auto& r : with_rms) b += r.estimated_particle_steps;
  BOOST_TEST(b < a);
}

// The throughput a plan divides by is probed at each size of the campaign, and an adaptive
// integrator's force evaluation costs kChebyshevEvaluationCost probe steps (throughput.hpp).
BOOST_AUTO_TEST_CASE(throughput_is_probed_per_size_and_priced_per_integrator) {
  jam::SimConfig run;
  run.integrator = "chebyshev";
  const jam::Throughput t = jam::measure_throughput(run, {64, 256});
  BOOST_TEST(t.per_size.size() == 2u);
  for (const auto& [n, speed] : t.per_size) BOOST_TEST(speed > 0.0);
  BOOST_TEST(t.evaluation_cost == jam::kChebyshevEvaluationCost);
  BOOST_TEST(t.core_seconds(64, 1e6) == 1e6 * jam::kChebyshevEvaluationCost / t.at(64),
             boost::test_tools::tolerance(1e-12));
  run.integrator = "heun";
  BOOST_TEST(jam::measure_throughput(run, {64}).evaluation_cost == 1.0);
  // A size not probed takes the nearest probed one in log N.
  jam::Throughput fixed;
  fixed.per_size = {{1024, 1.0}, {16384, 2.0}};
  BOOST_TEST(fixed.at(2048) == 1.0);  // 2x from 1024, 8x from 16384
  BOOST_TEST(fixed.at(8192) == 2.0);  // 8x from 1024, 2x from 16384
  BOOST_TEST(fixed.at(100) == 1.0);
  BOOST_TEST(fixed.at(1 << 20) == 2.0);
  BOOST_CHECK_THROW(jam::Throughput{}.at(64), std::logic_error);
}

// The stored measurements (reference/throughput.toml): linear in log N between their sizes,
// the nearest beyond them; a dimension they lack is none (then the probe), a table that does
// not add up is an error naming the file and the key.
BOOST_AUTO_TEST_CASE(stored_throughput_is_read_and_interpolated_in_log_n) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("jam-throughput-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "throughput.toml";
  std::ofstream(file) << "[2d]\nn = [256, 4096]\nparticle_steps_per_second = [1e8, 2e8]\n";
  using jam::stored_throughput;
  BOOST_TEST(*stored_throughput(file.string(), 2, 1024) == 1.5e8,
             boost::test_tools::tolerance(1e-12));  // half way in log N
  BOOST_TEST(*stored_throughput(file.string(), 2, 64) == 1e8);
  BOOST_TEST(*stored_throughput(file.string(), 2, 1 << 20) == 2e8);
  BOOST_TEST(!stored_throughput(file.string(), 3, 1024).has_value());
  BOOST_TEST(!stored_throughput((dir / "none.toml").string(), 2, 1024).has_value());
  // The shipped file has both dimensions; a plan priced from it says so.
  for (int dim : {2, 3})
    BOOST_TEST(stored_throughput(jam::stored_throughput_file(), dim, 1000).value_or(0) > 0);
  jam::SimConfig run;
  const jam::Throughput t = jam::plan_throughput(run, {64}, false);
  BOOST_TEST(t.source.at(64) == "stored, reference/throughput.toml");
  std::ofstream(file) << "[2d]\nn = [256, 4096]\nparticle_steps_per_second = [1e8]\n";
  try {
    stored_throughput(file.string(), 2, 1024);
    BOOST_TEST(false, "a table of 2 sizes and 1 speed was read");
  } catch (const std::runtime_error& e) {
    BOOST_TEST(std::string(e.what()).find("[2d] n and particle_steps_per_second: 2 and 1") !=
                   std::string::npos,
               e.what());
  }
  std::filesystem::remove_all(dir);
}

// Values that used to become failed runs, or to pass through silently, are refused up front
// with the file, line and key.
BOOST_AUTO_TEST_CASE(sizes_64_and_2_refused_not_failed_runs) {
  // N = 2 at phi_stop 0.86: a box of 1.6 against an interaction range of 2 x 1.7.
  const std::string e = rejection(replace(kGood, "sizes = [64, 128]", "sizes = [64, 2]"));
  BOOST_TEST(e.rfind("c.toml:3: sizes: 2: box length", 0) == 0u, e);
}

BOOST_AUTO_TEST_CASE(skin_1e300_refused) {
  BOOST_TEST(rejection(kGood + "skin = 1e300\n") == "c.toml:10: skin: 1e+300: must be in (0, 10]");
}

BOOST_AUTO_TEST_CASE(chain_phi_init_off_the_grid_by_1e_minus_10_refused) {
  const std::string chained =
      replace(kGood, "log10_rates = [-3, -3.5]", "log10_rates = [-3, -3.5]\nphi_step = 0.002");
  BOOST_TEST(rejection(chained + "chain_phi_init = [0, 0.82]\n") == "accepted");
  const std::string e = rejection(chained + "chain_phi_init = [0, 0.8200000001]\n");
  BOOST_TEST(e.rfind("c.toml:11: chain_phi_init: 0.8200000001", 0) == 0u, e);
  BOOST_TEST(e.find("at log10 rate -3.5: must be a multiple of phi_step (0.002), such as 0.82") !=
                 std::string::npos,
             e);
}

BOOST_AUTO_TEST_CASE(toml_escapes_of_control_characters_refused) {
  // The file itself is plain ASCII; the escapes decode to NUL, ESC and a non-ASCII letter.
  BOOST_TEST(rejection(replace(kGood, "name = \"t\"", R"(name = "a\u0000b")")) ==
             "c.toml:1: name: a string with the character 0x00 (escapes must give printable "
             "ASCII)");
  BOOST_TEST(rejection(replace(kGood, "name = \"t\"", R"(name = "x\u001b[31m")")) ==
             "c.toml:1: name: a string with the character 0x1b (escapes must give printable "
             "ASCII)");
  BOOST_TEST(rejection(replace(kGood, "output = \"out\"", R"(output = "ou\u0000t")")) ==
             "c.toml:9: output: a string with the character 0x00 (escapes must give printable "
             "ASCII)");
  BOOST_TEST(rejection(replace(kGood, "output = \"out\"", R"(output = "caf\u00e9")")) ==
             "c.toml:9: output: a string with the character 0xc3 (escapes must give printable "
             "ASCII)");
  BOOST_TEST(rejection(kGood + R"(expected_failures = ["phi_init: \u001b[2J"])" + "\n") ==
             "c.toml:10: expected_failures: a string with the character 0x1b (escapes must give "
             "printable ASCII)");
}

BOOST_AUTO_TEST_CASE(dot_and_dot_dot_are_never_campaign_names) {
  for (const char* name : {".", ".."}) {
    BOOST_TEST(rejection(replace(kGood, "name = \"t\"", fmt::format("name = \"{}\"", name))) ==
               fmt::format("c.toml:1: name: '{}': must be a non-empty word, not . or .. (it names "
                           "the report)",
                           name));
  }
}

BOOST_AUTO_TEST_CASE(a_million_samples_of_ten_sizes_refused_before_planning) {
  std::string big = replace(kGood, "samples = 3", "samples = 1000000");
  big = replace(big, "sizes = [64, 128]",
                "sizes = [64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768]");
  BOOST_TEST(rejection(big) ==
             "c.toml:6: samples: 1000000 x 10 sizes x 2 phi_init x 2 rates = 4e+07 runs (at most "
             "100000 per campaign file; split it with first_sample)");
}

// added-samples.toml (written by `jam campaign run --until-decided`, read on every resume) is
// outside input: a size or sample count that is not a whole number in range is refused naming
// the file, never cast to an integer; a good one is read, and one the campaign's samples has
// since overtaken is superseded.
BOOST_AUTO_TEST_CASE(added_samples_are_whole_numbers_in_range) {
  Campaign c = parse_campaign(kGood, "c.toml");
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "jam_test_campaign_file_added";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  c.output = dir.string();
  auto read = [&](const std::string& n, const std::string& samples) {
    std::ofstream(added_samples_path(c)) << fmt::format(
        "[[ensemble]]\nn = {}\nphi_init = 0.7\nlog10_rate = -3\nsamples = {}\n", n, samples);
    return read_added_samples(c);
  };
  const SampleCounts good = read("64", "6");
  BOOST_TEST_REQUIRE(good.size() == 1u);
  BOOST_TEST(good.begin()->first.n == 64);
  BOOST_TEST(good.begin()->second == 6);
  // The campaign's samples raised past an entry (3 -> 8 over 6): the entry is superseded, not
  // an error that leaves moving the file aside as the only way on.
  c.samples = 8;
  BOOST_TEST(read("64", "6").empty());
  c.samples = 3;
  for (const auto& [n, samples] : std::vector<std::pair<std::string, std::string>>{{"64.5", "6"},
                                                                                   {"-64", "6"},
                                                                                   {"1e300", "6"},
                                                                                   {"64", "6.5"},
                                                                                   {"64", "1e300"},
                                                                                   {"64", "nan"},
                                                                                   {"64", "-inf"},
                                                                                   {"nan", "6"}}) {
    BOOST_TEST_CONTEXT("n = " << n << ", samples = " << samples) {
      BOOST_CHECK_EXCEPTION(read(n, samples), CampaignError, [&](const CampaignError& e) {
        const std::string what = e.what();
        return what.rfind(added_samples_path(c), 0) == 0 &&
               what.find("whole numbers") != std::string::npos;
      });
    }
  }
  std::filesystem::remove_all(dir);
}

// [question]: what the campaign asks (campaign_file.hpp, CampaignQuestion). Each bad value is
// one line naming the file, the line, the key and the value.
BOOST_AUTO_TEST_CASE(the_question_is_read_and_each_bad_value_refused_naming_key_and_value) {
  const Campaign c = parse_campaign(kGood +
                                        "[question]\nphi_min = 0.83\nphi_max = 0.85\n"
                                        "checks = [\"finite_size\", \"jamming_point\"]\n"
                                        "alpha = 0.01\n",
                                    "c.toml");
  BOOST_TEST(c.question.states_range());
  BOOST_TEST(*c.question.phi_min == 0.83);
  BOOST_TEST(*c.question.phi_max == 0.85);
  BOOST_TEST((c.question.checks == std::vector<std::string>{"finite_size", "jamming_point"}));
  BOOST_TEST(*c.question.alpha == 0.01);
  // None stated: nothing asked.
  BOOST_TEST(!parse_campaign(kGood, "c.toml").question.states_range());
  BOOST_TEST(!parse_campaign(kGood, "c.toml").question.alpha.has_value());
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"phi_min = 1.2\nphi_max = 1.3\n",
       "c.toml:11: question.phi_min: 1.2: must be a packing in (0, 1)"},
      {"phi_min = 0.83\nphi_max = 0\n",
       "c.toml:12: question.phi_max: 0: must be a packing in (0, 1)"},
      {"phi_min = 0.85\nphi_max = 0.83\n",
       "c.toml:12: question.phi_max: 0.83: must exceed phi_min = 0.85"},
      {"phi_min = 0.83\n",
       "c.toml: question.phi_max: missing: phi_min and phi_max state the range judged together"},
      {"phi_min = 0.9\nphi_max = 0.95\n",
       "c.toml:11: question.phi_min: 0.9: must lie below phi_stop = 0.86 (no run reaches it)"},
      {"phi_min = 0.3\nphi_max = 0.6\n",
       "c.toml:12: question.phi_max: 0.6: must lie above the lowest phi_init = 0.7 (no run is "
       "compressed there)"},
      {"phi_min = \"0.83\"\nphi_max = 0.85\n", "c.toml:11: question.phi_min: must be a number"},
      {"checks = [\"finite_sizes\"]\n",
       "c.toml:11: question.checks: 'finite_sizes': unknown check"},
      {"checks = [\"chain\"]\n", "c.toml:11: question.checks: 'chain': unknown check"},
      {"checks = [\"zeta\", \"zeta\"]\n", "c.toml:11: question.checks: 'zeta': repeated"},
      {"alpha = 0.5\n", "c.toml:11: question.alpha: 0.5: must be in (0, 0.5)"},
      {"alpha = 0\n", "c.toml:11: question.alpha: 0: must be in (0, 0.5)"},
      {"margin = 0.1\n", "c.toml:11: question.margin: unknown key"},
  };
  for (const auto& [table, message] : bad) {
    const std::string got = rejection(kGood + "[question]\n" + table);
    BOOST_TEST(got.find(message) == 0, table << "-> " << got);
    BOOST_TEST(got.find('\n') == std::string::npos, got);
  }
  BOOST_TEST(rejection(kGood + "question = 0.84\n") ==
             "c.toml:10: question: must be a table ([question])");
}
