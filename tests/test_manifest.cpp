// campaign/manifest.hpp: `jam stats` reads a campaign's runs through its manifest.toml, the
// plan as the campaign ran it, instead of planning the campaign again. Through the executable:
// the manifest is written before the runs start; stats through it equal stats through the
// plan (every dataset; only the wall time and the checksum over it differ); a manifest whose
// plan inputs changed since (campaign.toml, added-samples.toml) is not used; a run file of
// another run under a run's name is left out as corrupt, saying which parameters differ.
#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "campaign/manifest.hpp"
#include "process.hpp"
#include "scratch.hpp"
#include "sim/io/hdf5_file.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("manifest");

jam::test::Outcome run_jam(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

/// A tiny campaign in kDir/<name>, run to the end.
fs::path run_campaign(const std::string& name, int samples) {
  fs::create_directories(kDir);
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << "name = \"" << name << "\"\ndim = 2\nsizes = [32, 64]\n"
                      << "phi_init = [0.80]\nlog10_rates = [-2.5]\nsamples = " << samples
                      << "\nphi_stop = 0.84\nphi_step = 0.002\nseed = 3\n"
                      << "relax_energy = \"1e-14\"\noutput = \"" << (kDir / name).string()
                      << "\"\n";
  const auto r = run_jam("campaign run " + file.string() + " --quiet");
  BOOST_TEST_REQUIRE(r.status == 0, r.output);
  return kDir / name;
}

/// Every dataset of two stats.h5 files, compared (the attributes hold the wall time).
bool same_tables(const fs::path& a, const fs::path& b) {
  const auto diff = jam::test::run_logged(
      kDir / "h5diff.txt", {"h5diff", "--exclude-attribute=/", a.string(), b.string()});
  return diff.status == 0;
}

}  // namespace

BOOST_AUTO_TEST_CASE(stats_through_the_manifest_equal_stats_through_the_plan) {
  const fs::path dir = run_campaign("same", 3);
  const auto manifest = jam::read_current_manifest(dir.string());
  BOOST_TEST_REQUIRE(manifest.has_value());
  BOOST_TEST(manifest->size() == 6u);  // 2 sizes x 3 samples, in plan order: the larger first
  BOOST_TEST(manifest->front().n == 64);
  BOOST_TEST(manifest->front().fingerprint_key.size() == 16u);

  BOOST_TEST_REQUIRE(run_jam("stats " + dir.string() + " --no-fit").status == 0);
  fs::copy_file(dir / "stats.h5", kDir / "through-manifest.h5");
  fs::rename(dir / "manifest.toml", kDir / "manifest.toml");
  BOOST_TEST(!jam::read_current_manifest(dir.string()).has_value());
  BOOST_TEST_REQUIRE(run_jam("stats " + dir.string() + " --no-fit").status == 0);
  BOOST_TEST(same_tables(kDir / "through-manifest.h5", dir / "stats.h5"),
             jam::test::slurp(kDir / "h5diff.txt"));
}

BOOST_AUTO_TEST_CASE(a_manifest_whose_plan_inputs_changed_is_not_used) {
  const fs::path dir = run_campaign("changed", 2);
  BOOST_TEST_REQUIRE(jam::read_current_manifest(dir.string()).has_value());
  // More samples asked in the stored campaign (as a raised `samples` does before its run):
  // the manifest no longer lists the plan.
  std::string text = jam::test::slurp(dir / "campaign.toml");
  text.replace(text.find("samples = 2"), 11, "samples = 3");
  std::ofstream(dir / "campaign.toml") << text;
  BOOST_TEST(!jam::read_current_manifest(dir.string()).has_value());
  const auto r = run_jam("stats " + dir.string() + " --no-fit");
  BOOST_TEST(r.status == 0, r.output);
  // Planned again: the two runs not yet made are counted as not finished.
  BOOST_TEST(r.output.find("2 skipped") != std::string::npos, r.output);
}

BOOST_AUTO_TEST_CASE(another_runs_file_under_a_runs_name_is_left_out_saying_what_differs) {
  const fs::path dir = run_campaign("swapped", 2);
  const fs::path runs = dir / "runs";
  fs::copy_file(runs / "n32_phi0.8000_r-2.50_s001.h5", runs / "n32_phi0.8000_r-2.50_s000.h5",
                fs::copy_options::overwrite_existing);
  BOOST_TEST_REQUIRE(jam::read_current_manifest(dir.string()).has_value());
  const auto r = run_jam("stats " + dir.string() + " --no-fit");
  BOOST_TEST(r.status == 0, r.output);
  BOOST_TEST(r.output.find("corrupt run n32_phi0.8000_r-2.50_s000 left out: run file belongs to "
                           "another run: seed=") != std::string::npos,
             r.output);
}
