// The stored reduced-scale reproduction (reference/results/reduced-<D>d/) as a regression
// baseline: CI reruns the part of each campaign described by reference/campaigns/
// reduced-<D>d-regression.toml (the smaller size, three rates, one sample of the stored
// campaign and four new ones) and `jam check regression` compares it with the stored stats.h5.
// The rerun sample must come out bitwise identical (same seed, same start, deterministic
// simulator built with -ffp-contract=off); the new samples' mean must agree with the stored
// ten within errors. That the check fails on planted differences (one ulp, a 15% shift) is
// shown in test_regression_check.cpp; here it must pass, and must have compared something.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "process.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-reduced-" + std::to_string(::getpid()));

using jam::test::Outcome;

Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

// The shipped regression campaign with its output moved into the test's directory.
fs::path campaign_in_temp(const std::string& name) {
  std::istringstream shipped(
      jam::test::slurp(fs::path(JAM_SOURCE_DIR) / "reference/campaigns" / (name + ".toml")));
  const fs::path file = kDir / (name + ".toml");
  std::ofstream out(file);
  for (std::string line; std::getline(shipped, line);) {
    if (line.rfind("output", 0) != 0) out << line << "\n";
  }
  out << "output = \"" << (kDir / name).string() << "\"\n";
  return file;
}

void check_against_stored(int dim) {
  const std::string name = "reduced-" + std::to_string(dim) + "d";
  const fs::path baseline = fs::path(JAM_SOURCE_DIR) / "reference/results" / name;
  BOOST_TEST_REQUIRE(fs::exists(baseline / "stats.h5"), baseline);
  const fs::path dir = kDir / (name + "-regression");

  const Outcome run =
      run_jam("campaign run " + campaign_in_temp(name + "-regression").string() + " --quiet");
  BOOST_TEST_REQUIRE(run.status == 0, run.output);
  const Outcome stats = run_jam("stats " + dir.string() + " --no-fit");
  BOOST_TEST_REQUIRE(stats.status == 0, stats.output);
  const Outcome check = run_jam("check regression " + dir.string() + " --against " +
                                baseline.string() + " --alpha 0.01");
  // 0, or 3 when the few new samples cannot exclude effects beyond the margin: never 1.
  BOOST_TEST((check.status == 0 || check.status == 3), check.output);

  const auto verdicts =
      nlohmann::json::parse(jam::test::slurp(dir / "checks-regression.json"))["verdicts"];
  int reruns = 0, new_samples = 0;
  for (const auto& v : verdicts) {
    const std::string what = v["case"].get<std::string>();
    const std::string status = v["status"].get<std::string>();
    if (what.find("rerun samples identical") != std::string::npos) {
      BOOST_TEST(status == "pass", what << ": " << v.dump());
      ++reruns;
    } else {
      BOOST_TEST(status != "fail", what << ": " << v.dump());
    }
    if (what.find("new samples against") != std::string::npos) ++new_samples;
  }
  // Three rates: every ensemble compared both ways, none skipped for want of data.
  BOOST_TEST(reruns == 3);
  BOOST_TEST(new_samples == 3);
}

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

}  // namespace

BOOST_FIXTURE_TEST_SUITE(reduced, Fixture)

BOOST_AUTO_TEST_CASE(reduced_2d_rerun_matches_stored_result) {
  check_against_stored(2);
}

BOOST_AUTO_TEST_CASE(reduced_3d_rerun_matches_stored_result) {
  check_against_stored(3);
}

BOOST_AUTO_TEST_SUITE_END()
