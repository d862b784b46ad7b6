// `jam pipeline FILE`, the main job, end to end through the executable on a small campaign:
// it runs, averages, judges and draws, printing the verdict table once (the report's, with the
// headlines; the check stage gives one line of counts); run again it redoes nothing.
#define BOOST_TEST_MODULE pipeline
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>

#include "process.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-pipeline-" + std::to_string(::getpid()));

struct Cleanup {
  ~Cleanup() { fs::remove_all(kDir); }
} cleanup;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

BOOST_AUTO_TEST_CASE(runs_judges_draws_and_then_redoes_nothing) {
  fs::create_directories(kDir);
  const fs::path file = kDir / "p.toml";
  std::ofstream(file) << "name = \"p\"\ndim = 2\nsizes = [64, 128]\nphi_init = [0.70]\n"
                         "log10_rates = [-2.5, -3.0]\nsamples = 3\nphi_stop = 0.86\n"
                         "phi_step = 0.002\ndt = 0.02\nseed = 5\n"
                      << "output = \"" << (kDir / "p").string() << "\"\n";
  const std::string args =
      "pipeline " + file.string() + " --jobs 2 --report " + (kDir / "report").string();
  const auto first = jam::test::run_jam_logged(kDir / "first.txt", args);
  // 0: done, whatever the verdicts say (they are in the report's summary).
  BOOST_TEST(first.status == 0, first.output);
  BOOST_TEST(fs::exists(kDir / "report" / "index.html"));
  BOOST_TEST(count(first.output, "status          check") == 1, first.output);
  BOOST_TEST(first.output.find("checks: ") != std::string::npos, first.output);
  const auto again = jam::test::run_jam_logged(kDir / "again.txt", args);
  BOOST_TEST(again.status == 0, again.output);
  for (const char* stage : {"stats: ", "checks: ", "report: "})
    BOOST_TEST(again.output.find(std::string(stage)) != std::string::npos, again.output);
  BOOST_TEST(count(again.output, "is up to date") == 3, again.output);
}
