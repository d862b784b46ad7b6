// Imports into external campaigns under faults (campaign/external_import.cpp): two imports at
// once both land, a file in runs/ that external.toml does not list is never replaced nor
// written through, an import killed with SIGKILL is completed by the next, and the smaller
// promises of docs/stability-and-faults.md ("Imports"). Concurrency runs real processes, and
// kills send a real SIGKILL.
#include <fmt/format.h>
#include <signal.h>

#include <boost/test/unit_test.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "campaign/external_campaign.hpp"
#include "campaign/run_plan.hpp"
#include "open_run_fixture.hpp"
#include "process.hpp"
#include "sim/io/open_run.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("jam_test_import_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// An open run of N 64 at rate 1e-3 from phi 0.8 with the given sample id.
std::string write_run(const fs::path& dir, std::int64_t sample, double offset = 0) {
  jam::OpenRun r = jam::test::open_run_of(64, 1e-3, 0.8, sample);
  for (double phi = 0.8; phi < 0.86; phi += 0.0003) {
    r.packing_fraction.push_back(phi);
    r.pressure.push_back(std::max(0.0, phi - 0.83) * (1 + 0.01 * static_cast<double>(sample)) +
                         1e-6 + offset);
  }
  const std::string path = (dir / fmt::format("run_s{}_o{}.h5", sample, offset)).string();
  jam::write_open_run(path, r);
  return path;
}

std::vector<std::string> write_runs(const fs::path& dir, int first, int count) {
  std::vector<std::string> files;
  for (int s = first; s < first + count; ++s) files.push_back(write_run(dir, s));
  return files;
}

/// The stored name of sample s of those runs.
fs::path stored(const fs::path& campaign, std::int64_t s) {
  return campaign / "runs" / (jam::run_name(64, 0.8, -3.0, s) + ".h5");
}

std::string joined(const std::vector<std::string>& files) {
  std::string text;
  for (const auto& f : files) text += " " + f;
  return text;
}

std::size_t h5_files_in(const fs::path& runs) {
  std::size_t count = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(runs, ec))
    if (e.path().extension() == ".h5") ++count;
  return count;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

// Issue 53, case 1: each import read external.toml, added its runs and wrote it back, so two at
// once kept about half of the 64 runs (5 of 5 trials), both exiting 0.
BOOST_AUTO_TEST_CASE(two_imports_at_once_both_land) {
  const fs::path src = scratch("concurrent_sources");
  const std::vector<std::string> first = write_runs(src, 0, 32), second = write_runs(src, 32, 32);
  const std::string seed = write_run(src, 1000);
  for (int trial = 0; trial < 5; ++trial) {
    BOOST_TEST_CONTEXT("trial " << trial) {
      const fs::path dir = scratch(fmt::format("concurrent_{}", trial)) / "c";
      jam::import_runs(dir.string(), {seed}, {});  // an existing external campaign
      const pid_t a = jam::test::spawn_jam("campaign import " + dir.string() + joined(first));
      const pid_t b = jam::test::spawn_jam("campaign import " + dir.string() + joined(second));
      BOOST_TEST(jam::test::wait_for(a) == 0);
      BOOST_TEST(jam::test::wait_for(b) == 0);
      const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());
      BOOST_TEST(c.runs.size() == 65u);
      BOOST_TEST(jam::unlisted_run_files(dir.string(), c).empty());
    }
  }
}

// Case 2: a file of someone's at a run's name in runs/ was replaced, and a symbolic link there
// written through (a file outside the campaign overwritten with HDF5).
BOOST_AUTO_TEST_CASE(a_file_or_link_in_runs_that_external_toml_does_not_list_is_left_alone) {
  const fs::path src = scratch("unlisted_sources"), dir = scratch("unlisted") / "c";
  const std::vector<std::string> files = write_runs(src, 0, 5);
  jam::import_runs(dir.string(), {files[0], files[3], files[4]}, {});
  std::ofstream(stored(dir, 1)) << "mine\n";
  const fs::path outside = scratch("unlisted_outside") / "thesis.tex";
  std::ofstream(outside) << "chapter 1\n";
  fs::create_symlink(outside, stored(dir, 2));

  const jam::ImportOutcome out = jam::import_runs(dir.string(), {files[1], files[2]}, {});
  BOOST_TEST(out.imported == 0);
  BOOST_REQUIRE(out.set_aside.size() == 2u);
  BOOST_TEST(
      contains(out.set_aside[0].reason, stored(dir, 1).string() + " is there and "
                                                                  "external.toml does not list it"),
      out.set_aside[0].reason);
  BOOST_TEST(contains(out.set_aside[1].reason, stored(dir, 2).string()), out.set_aside[1].reason);
  BOOST_TEST(slurp(stored(dir, 1)) == "mine\n");
  BOOST_TEST(slurp(outside) == "chapter 1\n");
  BOOST_TEST(fs::is_symlink(stored(dir, 2)));
  BOOST_TEST(jam::read_external_campaign(dir.string()).runs.size() == 3u);

  // status and stats name them.
  const auto status = jam::test::run_jam_logged(dir.parent_path() / "status.log",
                                                "campaign status " + dir.string());
  BOOST_TEST(status.status == 0, status.output);
  BOOST_TEST(contains(status.output, "unlisted  " + stored(dir, 1).string()), status.output);
  BOOST_TEST(contains(status.output, "unlisted  " + stored(dir, 2).string()), status.output);
  const auto stats =
      jam::test::run_jam_stderr(dir.parent_path() / "stats.err", "stats " + dir.string());
  BOOST_TEST(contains(stats.output, "warning: " + stored(dir, 1).string() +
                                        " is not in "
                                        "external.toml"),
             stats.output);
}

// Case 3: kill -9 during the first import left runs/ partly filled and no external.toml, and
// every later import refused the directory ("not empty and not an external campaign").
BOOST_AUTO_TEST_CASE(a_first_import_killed_with_sigkill_is_completed_by_the_next) {
  const fs::path src = scratch("killed_sources");
  const std::vector<std::string> files = write_runs(src, 0, 400);
  int killed_midway = 0;
  // Moments: as soon as the directory exists, and once a run has been copied.
  for (int trial = 0; trial < 6; ++trial) {
    BOOST_TEST_CONTEXT("trial " << trial) {
      const fs::path dir = scratch(fmt::format("killed_{}", trial)) / "c";
      fs::remove_all(dir);
      const std::string import = "campaign import " + dir.string() + joined(files);
      const pid_t pid = jam::test::spawn_jam(import);
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
      while (std::chrono::steady_clock::now() < deadline &&
             (trial % 2 == 0 ? !fs::exists(dir) : h5_files_in(dir / "runs") == 0)) {
        siginfo_t info{};
        if (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
            info.si_pid == pid)
          break;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      ::kill(pid, SIGKILL);
      jam::test::wait_for(pid);
      const std::size_t copied = h5_files_in(dir / "runs");
      if (copied > 0 && copied < files.size()) ++killed_midway;
      if (copied > 0) BOOST_TEST(jam::is_external_campaign(dir.string()));  // written first

      const auto status = jam::test::run_jam_logged(dir.parent_path() / "status.log",
                                                    "campaign status " + dir.string());
      if (jam::is_external_campaign(dir.string())) BOOST_TEST(status.status == 0, status.output);
      const auto again = jam::test::run_jam_logged(dir.parent_path() / "again.log", import);
      BOOST_TEST(again.status == 0, again.output);
      const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());
      BOOST_TEST(c.runs.size() == files.size());
      BOOST_TEST(jam::unlisted_run_files(dir.string(), c).empty());
      for (const auto& run : c.runs) BOOST_TEST(jam::stored_run_problem(dir.string(), run) == "");
    }
  }
  BOOST_TEST_MESSAGE(killed_midway << " of 6 kills landed while runs were being copied");
  BOOST_TEST(killed_midway >= 1);
}

// What an older jam left when killed during a first import (runs/ partly filled, no
// external.toml): the import completes it, adopting the copies whose checksum is a source's
// and naming the file that is no source's.
BOOST_AUTO_TEST_CASE(runs_an_interrupted_older_import_left_are_adopted_or_named) {
  const fs::path src = scratch("older_sources"), dir = scratch("older") / "c";
  const std::vector<std::string> files = write_runs(src, 0, 5);
  fs::create_directories(dir / "runs");
  for (int s : {0, 1, 2}) fs::copy_file(files[static_cast<std::size_t>(s)], stored(dir, s));
  std::ofstream(stored(dir, 9)) << "someone's\n";
  const jam::ImportOutcome out = jam::import_runs(dir.string(), files, {});
  BOOST_TEST(out.imported == 5);
  BOOST_TEST(out.set_aside.empty());
  const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());
  BOOST_TEST(c.runs.size() == 5u);
  BOOST_TEST(
      jam::unlisted_run_files(dir.string(), c) == std::vector<std::string>{stored(dir, 9).string()},
      boost::test_tools::per_element());
  BOOST_TEST(slurp(stored(dir, 9)) == "someone's\n");
}

// Case 18: an import of which nothing can be read made an empty campaign.
BOOST_AUTO_TEST_CASE(an_import_of_nothing_readable_writes_nothing) {
  const fs::path src = scratch("nothing_sources"), dir = scratch("nothing") / "c";
  std::ofstream(src / "notes.h5") << "not HDF5\n";
  const auto o = jam::test::run_jam_stderr(src / "err", "campaign import " + dir.string() + " " +
                                                            (src / "notes.h5").string() + " " +
                                                            (src / "missing.h5").string());
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(contains(o.output, "none of the 2 files can be imported, so nothing was written"),
             o.output);
  BOOST_TEST(!fs::exists(dir));
}

// Case 18: `--name ../../x` was accepted, and refused later by the report.
BOOST_AUTO_TEST_CASE(a_name_that_is_not_one_plain_word_is_refused) {
  const fs::path src = scratch("name_sources"), dir = scratch("name") / "c";
  const std::string run = write_run(src, 0);
  for (const std::string& name :
       std::vector<std::string>{"../../x", "a/b", ".", "..", ".hidden", "-x", "a b", "x\x1b[31m"}) {
    BOOST_TEST_CONTEXT(name) {
      jam::ImportOptions o;
      o.name = name;
      BOOST_CHECK_EXCEPTION(jam::import_runs(dir.string(), {run}, o), std::runtime_error,
                            [&](const std::runtime_error& e) {
                              return contains(e.what(), "--name '" + name + "': must be one word");
                            });
      BOOST_TEST(!fs::exists(dir));
    }
  }
  jam::ImportOptions o;
  o.name = "paper-2d_v1.2";
  jam::import_runs(dir.string(), {run}, o);
  BOOST_TEST(jam::read_external_campaign(dir.string()).name == "paper-2d_v1.2");
}

// Case 18: re-importing the source of a changed stored copy said "1 already there".
BOOST_AUTO_TEST_CASE(a_damaged_stored_copy_is_named_and_repaired_from_its_source) {
  const fs::path src = scratch("repair_sources"), dir = scratch("repair") / "c";
  const std::vector<std::string> files = write_runs(src, 0, 2);
  jam::import_runs(dir.string(), files, {});
  std::ofstream(stored(dir, 0), std::ios::app) << "x";  // one byte more: the checksum differs
  // A link put in place of the other copy: replaced, its target never written.
  const fs::path outside = scratch("repair_outside") / "keep.txt";
  std::ofstream(outside) << "keep\n";
  fs::remove(stored(dir, 1));
  fs::create_symlink(outside, stored(dir, 1));
  // Another file of sample 0 is set aside, and says the stored copy is damaged.
  const jam::ImportOutcome other =
      jam::import_runs(dir.string(), {write_run(scratch("repair_other"), 0, 0.5)}, {});
  BOOST_REQUIRE(other.set_aside.size() == 1u);
  BOOST_TEST(contains(other.set_aside[0].reason, "is damaged (changed since it was imported"),
             other.set_aside[0].reason);

  const jam::ImportOutcome out = jam::import_runs(dir.string(), files, {});
  BOOST_TEST(out.already == 0);
  BOOST_TEST(out.repaired == 2);
  BOOST_REQUIRE(out.notes.size() == 2u);
  BOOST_TEST(contains(out.notes[0], "was changed since it was imported"), out.notes[0]);
  BOOST_TEST(slurp(outside) == "keep\n");
  for (const auto& run : jam::read_external_campaign(dir.string()).runs)
    BOOST_TEST(jam::stored_run_problem(dir.string(), run) == "");
  BOOST_TEST(jam::import_runs(dir.string(), files, {}).already == 2);
}

// Case 18: the second run file of `jam sim` (which writes no sample id) was set aside with
// "give it another sample id", which could not be done without breaking its checksum.
BOOST_AUTO_TEST_CASE(run_files_of_jam_sim_get_sample_ids_of_their_own) {
  const fs::path src = scratch("sim_sources"), dir = scratch("sim") / "c";
  std::vector<std::string> files;
  for (int seed : {1, 2}) {
    const fs::path out = src / fmt::format("seed{}.h5", seed);
    const auto o = jam::test::run_jam_logged(
        src / "sim.log", fmt::format("sim --quiet --n 64 --phi-init 0.7 --phi-stop 0.72 --rate "
                                     "1e-2 --phi-step 0.005 --seed {} --out {}",
                                     seed, out.string()));
    BOOST_REQUIRE_MESSAGE(o.status == 0, o.output);
    files.push_back(out.string());
  }
  const std::string before = jam::file_checksum(files[1]);
  const jam::ImportOutcome out = jam::import_runs(dir.string(), files, {});
  BOOST_TEST(out.imported == 2);
  BOOST_TEST(out.set_aside.empty());
  BOOST_REQUIRE(out.notes.size() == 2u);
  BOOST_TEST(contains(out.notes[1], "imported as sample 1"), out.notes[1]);
  const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());
  BOOST_REQUIRE(c.runs.size() == 2u);
  BOOST_TEST(c.runs[0].sample == 0);
  BOOST_TEST(c.runs[1].sample == 1);
  BOOST_TEST(jam::file_checksum(files[1]) == before);  // the files are not changed
  for (const auto& run : c.runs) BOOST_TEST(jam::stored_run_problem(dir.string(), run) == "");
  // Again: both already there, under the ids they were given.
  const jam::ImportOutcome again = jam::import_runs(dir.string(), {files[1], files[0]}, {});
  BOOST_TEST(again.already == 2);
  BOOST_TEST(jam::read_external_campaign(dir.string()).runs.size() == 2u);
}

// Case 11: `--phi-step 1e-8` was accepted, then stats refused the grid (more than 10^6
// points), and the step could not be changed.
BOOST_AUTO_TEST_CASE(a_phi_step_whose_grid_stats_would_refuse_is_refused_at_import) {
  const fs::path src = scratch("step_sources"), dir = scratch("step") / "c";
  const std::string run = write_run(src, 0);
  const auto o = jam::test::run_jam_stderr(
      src / "err", "campaign import " + dir.string() + " " + run + " --phi-step 1e-8");
  BOOST_TEST(o.status == 2, o.output);
  BOOST_TEST(contains(o.output,
                      "--phi-step 1e-08: a grid of up to 1e+08 points over packings "
                      "in (0, 1), more than the statistics' limit of 1e+06"),
             o.output);
  BOOST_TEST(!fs::exists(dir));
  jam::ImportOptions fine;
  fine.phi_step = 1e-6;
  BOOST_TEST(jam::import_runs(dir.string(), {run}, fine).imported == 1);
  // Another step is refused; but a step an older jam recorded beyond the limit can be replaced.
  jam::ImportOptions other;
  other.phi_step = 0.001;
  BOOST_CHECK_THROW(jam::import_runs(dir.string(), {run}, other), std::runtime_error);
  std::string text = slurp(dir / "external.toml");
  const auto at = text.find("phi_step = ");
  BOOST_REQUIRE(at != std::string::npos);
  text.replace(at, text.find('\n', at) - at, "phi_step = 1e-08");
  std::ofstream(dir / "external.toml") << text;
  BOOST_TEST(jam::read_external_campaign(dir.string()).phi_step == 1e-8);
  const jam::ImportOutcome out = jam::import_runs(dir.string(), {run}, other);
  BOOST_TEST(out.already == 1);
  BOOST_TEST(jam::read_external_campaign(dir.string()).phi_step == 0.001);
}
