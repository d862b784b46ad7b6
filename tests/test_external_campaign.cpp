// External campaigns (campaign/external_campaign.hpp): runs jam did not plan join a campaign
// directory only when they are open runs of its model, each set-aside file keeps its reason,
// nothing the user had is touched, and the statistics average what was imported.
#include <fmt/format.h>

#include <array>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "campaign/external_campaign.hpp"
#include "open_run_fixture.hpp"
#include "process.hpp"
#include "sim/io/open_run.hpp"
#include "stats/campaign_stats.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("jam_test_external_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// An open run of N 64 at rate 10^log10_rate from phi 0.8, with a pressure that grows with phi
/// and a sample-dependent offset, on an output grid of its own (spacing 0.0003).
std::string write_run(const fs::path& dir, double log10_rate, std::int64_t sample,
                      double diameter_ratio = 1.4) {
  jam::OpenRun r = jam::test::open_run_of(64, std::pow(10.0, log10_rate), 0.8, sample);
  r.diameter_ratio = diameter_ratio;
  for (double phi = 0.8; phi < 0.86; phi += 0.0003) {
    r.packing_fraction.push_back(phi);
    r.pressure.push_back(std::max(0.0, phi - 0.83) * (1 + 0.01 * static_cast<double>(sample)) +
                         1e-6);
  }
  const std::string path =
      (dir / fmt::format("run_r{}_s{}_d{}.h5", log10_rate, sample, diameter_ratio)).string();
  jam::write_open_run(path, r);
  return path;
}

}  // namespace

BOOST_AUTO_TEST_CASE(runs_of_the_model_join_and_others_are_set_aside_with_a_reason) {
  const fs::path src = scratch("sources"), dir = scratch("campaign") / "c";
  std::vector<std::string> files;
  for (double lr : {-3.0, -4.0})
    for (int s : {0, 1}) files.push_back(write_run(src, lr, s));
  const std::string other = write_run(src, -3.0, 5, 1.35);
  const fs::path junk = src / "notes.h5";
  std::ofstream(junk) << "not HDF5\n";
  files.push_back(other);
  files.push_back(junk.string());
  const auto before = fs::last_write_time(files[0]);

  const jam::ImportOutcome out = jam::import_runs(dir.string(), files, {});
  BOOST_TEST(out.imported == 4);
  BOOST_REQUIRE(out.set_aside.size() == 2u);
  BOOST_TEST(
      out.set_aside[0].reason.find("diameter_ratio 1.35, the campaign's 1.4") != std::string::npos,
      out.set_aside[0].reason);
  BOOST_TEST(out.set_aside[1].reason.find("notes.h5") != std::string::npos,
             out.set_aside[1].reason);
  BOOST_TEST((fs::last_write_time(files[0]) == before));  // the sources are never changed

  const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());
  BOOST_TEST(c.runs.size() == 4u);
  BOOST_TEST(c.set_aside.size() == 2u);
  BOOST_TEST(c.diameter_ratio == 1.4);
  BOOST_TEST(fs::exists(dir / "runs" / "n64_phi0.8000_r-3.00_s001.h5"));

  // Again: nothing new; the same sample id from another file is set aside, naming the first.
  const jam::ImportOutcome again = jam::import_runs(dir.string(), {files[0], files[1]}, {});
  BOOST_TEST(again.imported == 0);
  BOOST_TEST(again.already == 2);
  const fs::path twin_dir = scratch("twin");
  const std::string twin = write_run(twin_dir, -3.0, 0);
  {
    // Same ensemble and sample, other numbers.
    jam::OpenRun r = jam::read_open_run(twin);
    r.pressure[10] *= 2;
    fs::remove(twin);
    jam::write_open_run(twin, r);
  }
  const jam::ImportOutcome dup = jam::import_runs(dir.string(), {twin}, {});
  BOOST_REQUIRE(dup.set_aside.size() == 1u);
  BOOST_TEST(dup.set_aside[0].reason.find("already imported") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(statistics_average_the_imported_runs_and_leave_out_a_changed_one) {
  const fs::path src = scratch("stats_sources"), dir = scratch("stats") / "c";
  std::vector<std::string> files;
  for (double lr : {-3.0, -4.0})
    for (int s : {0, 1, 2}) files.push_back(write_run(src, lr, s));
  jam::import_runs(dir.string(), files, {});
  jam::stats::StatsOptions o;
  o.fit = false;
  const auto s = jam::stats::compute_campaign_stats(dir.string(), o);
  BOOST_REQUIRE(s.ensembles.size() == 2u);
  for (const auto& e : s.ensembles) {
    BOOST_TEST(e.constant_phi.sample_ids.size() == 3u);
    BOOST_TEST(!e.constant_z.has_value());  // the runs carry no Z
    // The campaign's grid (0.0005), interpolated from the runs' own (0.0003).
    BOOST_TEST(std::abs(e.constant_phi.grid[1] - e.constant_phi.grid[0] - 0.0005) < 1e-12);
  }
  // A stored run changed after its import is left out, named.
  const fs::path stored = dir / "runs" / "n64_phi0.8000_r-3.00_s002.h5";
  {
    jam::OpenRun r = jam::read_open_run(stored.string());
    r.pressure[3] += 1;
    fs::remove(stored);
    jam::write_open_run(stored.string(), r);
  }
  const auto t = jam::stats::compute_campaign_stats(dir.string(), o);
  BOOST_TEST(t.runs_skipped == 1);
  BOOST_TEST(t.runs_averaged == 5);
}

BOOST_AUTO_TEST_CASE(nothing_of_the_users_is_touched) {
  // A directory with a file of the user's, and a planned campaign: both refused, both intact.
  const fs::path src = scratch("user_sources");
  const std::string run = write_run(src, -3.0, 0);
  const fs::path user = scratch("user");
  std::ofstream(user / "thesis.tex") << "chapter 1\n";
  BOOST_CHECK_THROW(jam::import_runs(user.string(), {run}, {}), std::runtime_error);
  BOOST_TEST(jam::test::slurp(user / "thesis.tex") == "chapter 1\n");
  BOOST_TEST(!fs::exists(user / "runs"));
  const fs::path planned = scratch("planned");
  std::ofstream(planned / "campaign.toml") << "name = \"x\"\n";
  BOOST_CHECK_THROW(jam::import_runs(planned.string(), {run}, {}), std::runtime_error);
  BOOST_TEST(!fs::exists(planned / "external.toml"));
  // And `jam campaign run` never runs into an external campaign.
  const fs::path ext = scratch("ext") / "c";
  jam::import_runs(ext.string(), {run}, {});
  const fs::path file = scratch("ext_file") / "c.toml";
  std::ofstream(file) << "name = \"c\"\ndim = 2\nsizes = [64]\nphi_init = [0.8]\n"
                      << "log10_rates = [-3.0]\nsamples = 1\nphi_stop = 0.81\nseed = 1\n"
                      << "output = \"" << ext.string() << "\"\n";
  const auto o =
      jam::test::run_jam_stderr(file.parent_path() / "err", "campaign run " + file.string());
  BOOST_TEST(o.status == 2);
  BOOST_TEST(o.output.find("external campaign") != std::string::npos, o.output);
}

// An external.toml edited by hand: n, sample and dim are whole numbers in range, refused with
// the key and the value otherwise (never cast out of an integer's range).
BOOST_AUTO_TEST_CASE(counts_of_an_edited_external_file_are_whole_numbers) {
  const fs::path src = scratch("edit_sources");
  const fs::path dir = scratch("edit") / "c";
  jam::import_runs(dir.string(), {write_run(src, -3.0, 0)}, {});
  const std::string text = jam::test::slurp(dir / "external.toml");
  BOOST_TEST_REQUIRE(jam::read_external_campaign(dir.string()).runs.size() == 1u);
  // (from, to, message) as an array: clang 14 does not capture a structured binding.
  for (const auto& edit : std::vector<std::array<std::string, 3>>{
           {"n = 64", "n = 1e30", "n = 1e+30 is not"},
           // beyond 2^53: judged as written, not rounded to 2^53
           {"n = 64", "n = 9007199254740993", "n = 9007199254740993 is not"},
           {"sample = 0", "sample = 0.5", "sample = 0.5 is"},
           {"dim = 2", "dim = 7", "dim = 7 is not"},
           // The open run format's own rules (open_run_limits.json), as on import: a record
           // edited past them is refused, not averaged.
           {"n = 64", "n = 63", "n 63 must be even"},
           {"name = 'c'", "name = '../../x'", "name '../../x' is not one plain word"},
           {"diameter_ratio = 1.3999999999999999", "diameter_ratio = 5.0",
            "diameter_ratio 5 must be in [1, 2]"},
           {"dynamics = 'overdamped'", "dynamics = 'brownian'", "dynamics 'brownian'"},
           {"phi_init = 0.80000000000000004", "phi_init = 5.0", "phi_init 5 must be in (0, 1)"}}) {
    const std::string &from = edit[0], &to = edit[1], &message = edit[2];
    BOOST_TEST_CONTEXT(to) {
      std::string edited = text;
      const auto at = edited.find(from);
      BOOST_TEST_REQUIRE(at != std::string::npos);
      std::ofstream(dir / "external.toml") << edited.replace(at, from.size(), to);
      BOOST_CHECK_EXCEPTION(jam::read_external_campaign(dir.string()), std::runtime_error,
                            [&](const std::runtime_error& e) {
                              return std::string(e.what()).find(message) != std::string::npos;
                            });
    }
  }
}

// A run imported from a directory whose name is not ASCII: external.toml escapes it (jam's TOML
// files are plain ASCII, campaign/toml_file.hpp) and reads it back as it was.
BOOST_AUTO_TEST_CASE(a_source_path_beyond_ascii_reads_back) {
  const fs::path src = scratch("sources_nonascii") / "donn\u00e9es \u03c6";
  fs::create_directories(src);
  const fs::path dir = scratch("nonascii") / "c";
  const std::string run = write_run(src, -3.0, 0);
  jam::import_runs(dir.string(), {run}, {});
  const auto c = jam::read_external_campaign(dir.string());
  BOOST_TEST_REQUIRE(c.runs.size() == 1u);
  BOOST_TEST(c.runs[0].source == fs::absolute(run).lexically_normal().string());
  BOOST_TEST(jam::test::slurp(dir / "external.toml").find("\\u00E9") != std::string::npos);
}
