// A campaign compared with itself passes whatever it holds, so `jam check compare` refuses it
// in every form, with one line and exit 2 (checks/same_campaign.hpp): DIR and REF one
// directory (also spelled another way), an import of REF's own run files, `compare_with`
// naming the campaign itself, and two copies of one stats.h5. A `compare_with` directory that
// does not exist is named as such by `jam pipeline`, before any run.
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"
#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("compare-self");

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A tiny campaign file writing to `output`, with compare_with when given.
std::string campaign_text(const fs::path& output, const std::string& compare_with = "") {
  return "name = \"self\"\ndim = 2\nsizes = [64]\nphi_init = [0.80]\nlog10_rates = [-2.5]\n"
         "samples = 2\nphi_stop = 0.84\nphi_step = 0.002\ndt = 0.02\nseed = 5\noutput = \"" +
         output.string() + "\"\n" +
         (compare_with.empty() ? "" : "compare_with = [\"" + compare_with + "\"]\n");
}

/// REF: the tiny campaign run and averaged once; its campaign file names itself in
/// compare_with.
const fs::path& ref() {
  static const fs::path dir = [] {
    fs::create_directories(kDir);
    const fs::path out = kDir / "ref";
    std::ofstream(kDir / "ref.toml") << campaign_text(out, out.string());
    for (const std::string& args :
         {"campaign run " + (kDir / "ref.toml").string() + " --jobs 2", "stats " + out.string()}) {
      const auto o = jam::test::run_jam_logged(kDir / "setup.log", args);
      if (o.status != 0) throw std::runtime_error(args + ": " + o.output);
    }
    return out;
  }();
  return dir;
}

}  // namespace

BOOST_AUTO_TEST_CASE(one_directory_is_refused_however_spelled) {
  for (const fs::path& other : {ref(), ref() / ".", kDir / ".." / kDir.path().filename() / "ref"}) {
    const auto o = jam::test::run_jam_stderr(
        kDir / "err.txt", "check compare " + ref().string() + " --against " + other.string());
    BOOST_TEST(o.status == 2, o.output);
    BOOST_TEST(has(o.output, "are one directory: a campaign compared with itself"), o.output);
    BOOST_TEST(!fs::exists(ref() / "checks-compare.json"));  // nothing that reads as a result
  }
}

BOOST_AUTO_TEST_CASE(an_import_of_refs_own_run_files_is_refused) {
  const fs::path copy = kDir / "imported";
  std::string args = "campaign import " + copy.string();
  for (const auto& e : fs::directory_iterator(ref() / "runs"))
    if (e.path().extension() == ".h5") args += " " + e.path().string();
  BOOST_TEST_REQUIRE(jam::test::run_jam_logged(kDir / "import.log", args).status == 0);
  BOOST_TEST_REQUIRE(
      jam::test::run_jam_logged(kDir / "stats.log", "stats " + copy.string()).status == 0);
  const auto o = jam::test::run_jam_stderr(
      kDir / "err.txt", "check compare " + copy.string() + " --against " + ref().string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(has(o.output, "hold the same run files (2 of DIR's 2"), o.output);
  BOOST_TEST(!fs::exists(copy / "checks-compare.json"));
}

BOOST_AUTO_TEST_CASE(compare_with_naming_the_campaign_itself_is_refused) {
  const auto o =
      jam::test::run_jam_stderr(kDir / "err.txt", "check all " + ref().string() + " --no-lmp");
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(has(o.output, "are one directory"), o.output);
  BOOST_TEST(!fs::exists(ref() / "checks.json"));
}

BOOST_AUTO_TEST_CASE(two_copies_of_one_stats_file_are_refused) {
  for (const char* d : {"copy-a", "copy-b"}) {
    fs::create_directories(kDir / d);
    fs::copy_file(ref() / "stats.h5", kDir / d / "stats.h5", fs::copy_options::overwrite_existing);
  }
  const auto o =
      jam::test::run_jam_stderr(kDir / "err.txt", "check compare " + (kDir / "copy-a").string() +
                                                      " --against " + (kDir / "copy-b").string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(has(o.output, "hold the same runs (2 of DIR's runs have the pressure of one of REF's"),
             o.output);
}

BOOST_AUTO_TEST_CASE(a_missing_compare_with_directory_is_named_before_any_run) {
  const fs::path file = kDir / "missing.toml", output = kDir / "missing";
  std::ofstream(file) << campaign_text(output, (kDir / "nowhere").string());
  const auto o =
      jam::test::run_jam_stderr(kDir / "err.txt", "pipeline " + file.string() + " --no-lmp");
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(has(o.output,
                 "compare_with: " + (kDir / "nowhere").string() + ": no such campaign directory"),
             o.output);
  BOOST_TEST(!has(o.output, "cannot read campaign file"), o.output);
  BOOST_TEST(!fs::exists(output / "runs"));  // refused before any run
}
