// stats.h5 is judged only when it can be trusted, through the executable: `jam check` refuses a
// stats.h5 older than its campaign's runs (runs imported after `jam stats`, by their digest
// even when their modification times say otherwise, not for a file merely touched) and one
// whose tables were changed by hand (its checksum), in one line naming the file; `jam stats
// --refit` refuses the changed file too and keeps the digest of the runs.
#include <fmt/format.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "open_run_fixture.hpp"
#include "process.hpp"
#include "scratch.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("fresh");

/// An open run of N 64 from phi 0.8 at rate 10^log10_rate whose pressure is `factor` times a
/// common curve (with a small sample-dependent scatter).
std::string write_run(const std::string& stem, double log10_rate, std::int64_t sample,
                      double factor) {
  jam::OpenRun r = jam::test::open_run_of(64, std::pow(10.0, log10_rate), 0.8, sample);
  for (double phi = 0.8; phi < 0.86; phi += 0.0005) {
    r.packing_fraction.push_back(phi);
    const double scatter = 1 + 0.02 * std::sin(3.0 * static_cast<double>(sample) + 40 * phi);
    r.pressure.push_back(factor * (std::max(0.0, phi - 0.82) + 1e-4) * scatter);
  }
  const fs::path path = kDir / "sources" / fmt::format("{}_r{}_s{}.h5", stem, log10_rate, sample);
  fs::create_directories(path.parent_path());
  jam::write_open_run(path.string(), r);
  return path.string();
}

jam::test::Outcome jam_run(const std::string& args) {
  return jam::test::run_jam_logged(kDir / "output.txt", args);
}

/// An external campaign DIR of `samples` samples at two rates, its pressure `factor` times the
/// common curve, sample numbers from `first`.
void import(const fs::path& dir, double factor, int first, int samples) {
  std::string files;
  for (double lr : {-3.0, -4.0})
    for (int s = first; s < first + samples; ++s)
      files += " " + write_run(dir.filename().string() + std::to_string(factor), lr, s, factor);
  const auto o = jam_run("campaign import " + dir.string() + files);
  BOOST_TEST_REQUIRE(o.status == 0, o.output);
}

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// Scales every pressure table of DIR/stats.h5 by `factor`, as a hand edit would (h5py).
void scale_pressures(const fs::path& stats, double factor) {
  const int status = jam::run_program({"/usr/bin/python3", "-c",
                                       "import h5py, sys\n"
                                       "f = h5py.File(sys.argv[1], 'r+')\n"
                                       "for e in f['ensembles'].values():\n"
                                       "    d = e['constant_phi/pressure_samples']\n"
                                       "    d[...] = d[...] * float(sys.argv[2])\n",
                                       stats.string(), std::to_string(factor)});
  BOOST_TEST_REQUIRE(status == 0);
}

}  // namespace

BOOST_AUTO_TEST_CASE(check_refuses_stats_older_than_runs_imported_after_it) {
  const fs::path dir = kDir / "imported";
  import(dir, 1.0, 0, 4);
  BOOST_TEST_REQUIRE(jam_run("stats --no-fit " + dir.string()).status == 0);
  {
    const jam::h5::File f = jam::h5::File::open_read((dir / "stats.h5").string());
    BOOST_TEST(f.read_attribute_string("inputs_checksum").size() == 16u);
    BOOST_TEST(f.read_attribute_string("checksum").size() == 16u);
  }
  const auto fresh = jam_run("check sample_pairs " + dir.string());
  BOOST_TEST(fresh.status != 2, fresh.output);
  fs::remove(dir / "checks-sample_pairs.json");

  // Runs with +50% pressure imported after `jam stats`: refused, naming the newer input.
  import(dir, 1.5, 4, 4);
  const auto stale = jam_run("check sample_pairs " + dir.string());
  BOOST_TEST(stale.status == 2, stale.output);
  BOOST_TEST(lines(stale.output) == 1u, stale.output);
  BOOST_TEST(stale.output.find((dir / "stats.h5").string() + ": out of date") != std::string::npos,
             stale.output);
  BOOST_TEST(stale.output.find("external.toml is newer than it") != std::string::npos,
             stale.output);
  BOOST_TEST(stale.output.find("run `jam stats " + dir.string() + "`") != std::string::npos,
             stale.output);
  BOOST_TEST(!fs::exists(dir / "checks-sample_pairs.json"));

  // The same with every modification time put back before stats.h5's: the digest decides.
  const auto old = fs::last_write_time(dir / "stats.h5") - std::chrono::hours(1);
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename() != "stats.h5") fs::last_write_time(e.path(), old);
  const auto hidden = jam_run("check sample_pairs " + dir.string());
  BOOST_TEST(hidden.status == 2, hidden.output);
  BOOST_TEST(hidden.output.find("its runs are not those it was averaged from") != std::string::npos,
             hidden.output);

  // Averaged again, it is judged; touched without a change, it is still current.
  BOOST_TEST_REQUIRE(jam_run("stats --no-fit " + dir.string()).status == 0);
  fs::last_write_time(dir / "external.toml",
                      fs::last_write_time(dir / "stats.h5") + std::chrono::hours(1));
  const auto again = jam_run("check sample_pairs " + dir.string());
  BOOST_TEST(again.status != 2, again.output);
  BOOST_TEST(fs::exists(dir / "checks-sample_pairs.json"));
}

BOOST_AUTO_TEST_CASE(stats_tables_changed_by_hand_are_refused_naming_the_file) {
  const fs::path dir = kDir / "dir", ref = kDir / "ref";
  import(dir, 1.0, 0, 4);
  import(ref, 1.0, 10, 4);  // the same physics, other samples
  for (const fs::path& d : {dir, ref})
    BOOST_TEST_REQUIRE(jam_run("stats --no-fit " + d.string()).status == 0);
  const std::string compare = "check compare " + dir.string() + " --against " + ref.string();
  const auto same = jam_run(compare);
  BOOST_TEST(same.status != 2, same.output);

  // REF's tables x1.15 by hand: refused in one line naming REF's stats.h5, judged nothing.
  fs::remove(dir / "checks-compare.json");
  scale_pressures(ref / "stats.h5", 1.15);
  const auto changed = jam_run(compare);
  BOOST_TEST(changed.status == 2, changed.output);
  BOOST_TEST(lines(changed.output) == 1u, changed.output);
  BOOST_TEST(changed.output.find((ref / "stats.h5").string() + ": checksum") != std::string::npos,
             changed.output);
  BOOST_TEST(changed.output.find("changed since `jam stats` wrote it") != std::string::npos,
             changed.output);
  BOOST_TEST(!fs::exists(dir / "checks-compare.json"));
  // The refit reads the averages: refused too.
  const auto refit = jam_run("stats --refit --no-fit " + ref.string());
  BOOST_TEST(refit.status == 2, refit.output);
  BOOST_TEST(refit.output.find("changed since `jam stats` wrote it") != std::string::npos,
             refit.output);

  // A refit of a sound file keeps the digest of the runs the averages came from.
  BOOST_TEST_REQUIRE(jam_run("stats --no-fit " + ref.string()).status == 0);
  std::string digest;
  {
    const jam::h5::File f = jam::h5::File::open_read((ref / "stats.h5").string());
    digest = f.read_attribute_string("inputs_checksum");
  }
  BOOST_TEST_REQUIRE(jam_run("stats --refit --no-fit " + ref.string()).status == 0);
  const jam::h5::File f = jam::h5::File::open_read((ref / "stats.h5").string());
  BOOST_TEST(f.read_attribute_string("inputs_checksum") == digest);
}
