// What an attacker's HDF5 files did to jam's readers, one test per reproduction: shapes and
// classes are checked before values are read (an array where a scalar belongs, points_*
// columns of unequal length, a negative next_output), the run file's checksum walk does
// bounded work (a flipped dimension, a group that contains itself, an unwritten chunked
// dataset), and a FIFO is refused before it is opened. Each reader runs in a child process
// with a time limit, so that a crash or a hang fails its test and not the suite, and the
// child's memory growth is measured.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "checks/stats_data.hpp"
#include "hostile_hdf5.hpp"
#include "process.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/run_file.hpp"
#include "sim/io/sealed_file.hpp"
#include "sim/run/compression_run.hpp"
#include "stats/campaign_stats.hpp"

namespace fs = std::filesystem;
using jam::test::Editor;
using jam::test::ValueClass;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-hdf5-shapes-" + std::to_string(::getpid()));

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

struct Isolated {
  int status = 0;            // exit status, or minus the signal that ended the child
  std::string message;       // what the reader said: its error, or "" when it succeeded
  long grown_megabytes = 0;  // the child's peak memory beyond what it started with
};

long peak_kilobytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

/// Runs `read` in a child process killed after `seconds`; its message comes back through a
/// pipe. A reader that crashes or hangs ends the child, not the test executable.
Isolated isolated(const std::function<std::string()>& read, unsigned seconds = 60) {
  int fds[2];
  BOOST_REQUIRE(::pipe(fds) == 0);
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  BOOST_REQUIRE(pid >= 0);
  if (pid == 0) {
    // The test framework's handlers would carry on with the other tests in this child.
    for (int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGALRM}) std::signal(sig, SIG_DFL);
    ::close(fds[0]);
    ::alarm(seconds);
    const long before = peak_kilobytes();
    std::string message;
    try {
      message = read();
    } catch (const std::exception& e) {
      message = e.what();
    }
    const std::string out = std::to_string((peak_kilobytes() - before) / 1024) + "\n" + message;
    [[maybe_unused]] const auto written = ::write(fds[1], out.data(), out.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string out;
  char buffer[4096];
  for (ssize_t got; (got = ::read(fds[0], buffer, sizeof buffer)) > 0;) out.append(buffer, got);
  ::close(fds[0]);
  Isolated r;
  r.status = jam::test::wait_for(pid);
  const auto newline = out.find('\n');
  if (newline != std::string::npos) {
    r.grown_megabytes = std::stol(out.substr(0, newline));
    r.message = out.substr(newline + 1);
  }
  return r;
}

/// The child ended normally and said `text`.
void expect(const Isolated& r, const std::string& text) {
  BOOST_TEST(r.status == 0, "the reader crashed or hung (status " << r.status << ")");
  BOOST_TEST(r.message.find(text) != std::string::npos, r.message);
  BOOST_TEST(r.message.find('\n') == std::string::npos, "not one line: " << r.message);
}

fs::path valid_run_file(const std::string& name) {
  return jam::test::valid_run_file(kDir, name);
}

std::string run_file_problem(const fs::path& file) {
  return jam::run_file_problem(file.string());
}

const std::string kFingerprint = "template-checkpoint";
const std::string kIdentity = "template-start";

std::string read_checkpoint(const fs::path& file) {
  try {
    jam::read_checkpoint<2>(file.string(), kFingerprint);
    return "";
  } catch (const jam::CorruptCheckpoint& e) {
    return std::string("corrupt: ") + e.what();
  }
}

/// A copy of the template checkpoint, edited and sealed again: a forged but valid seal, so
/// that only the reader's own checks stand between the edit and the run.
fs::path forged_checkpoint(const std::string& name, const std::function<void(Editor&)>& edit) {
  const fs::path file = kDir / name;
  jam::test::write_template_checkpoint(file.string(), kFingerprint);
  BOOST_REQUIRE(read_checkpoint(file).empty());
  {
    Editor e(file);
    edit(e);
  }
  jam::seal_file(file.string());
  return file;
}

/// The checks' reader of a stats.h5 refuses the one in dir and says `what`.
void expect_checks_stats_reader(const fs::path& dir, const std::string& what) {
  expect(isolated([&] {
           jam::checks::read_stats(dir.string());
           return std::string();
         }),
         what);
}

/// Both readers of a stats.h5, the checks' and `jam stats --refit`'s, refuse the one in dir
/// and say `what`.
void expect_both_stats_readers(const fs::path& dir, const std::string& what) {
  expect_checks_stats_reader(dir, what);
  jam::stats::StatsOptions o;
  o.fit = false;
  expect(isolated([&] {
           jam::stats::refit_campaign_stats(dir.string(), o);
           return std::string();
         }),
         what);
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(hdf5_shapes, Fixture)

BOOST_AUTO_TEST_CASE(array_complete_attribute_in_run_file_is_refused_not_read) {
  const fs::path file = valid_run_file("complete.h5");
  Editor(file).set_attribute(".", "complete", ValueClass::kInteger, {4000});
  expect(isolated([&] { return run_file_problem(file); }),
         "attribute 'complete' is an array of 4000, expected a scalar");
}

BOOST_AUTO_TEST_CASE(array_checksum_attribute_in_run_file_is_refused_not_read) {
  const fs::path file = valid_run_file("checksum.h5");
  Editor(file).set_attribute(".", "checksum", ValueClass::kString, {4000});
  expect(isolated([&] { return run_file_problem(file); }),
         "attribute 'checksum' is an array of 4000, expected a scalar");
}

BOOST_AUTO_TEST_CASE(attribute_of_another_class_names_the_class) {
  const fs::path file = valid_run_file("class.h5");
  Editor(file).set_attribute(".", "complete", ValueClass::kString, {});
  expect(isolated([&] { return run_file_problem(file); }),
         "attribute 'complete' is a string, expected an integer");
  Editor(file).set_attribute(".", "checksum", ValueClass::kCompound, {});
  Editor(file).set_int("complete", 1);
  expect(isolated([&] { return run_file_problem(file); }),
         "attribute 'checksum' is a compound value, expected a string");
  // h5py writes str as a variable-length string: read, then judged by the checksum.
  Editor(file).set_attribute(".", "checksum", ValueClass::kVariableString, {});
  expect(isolated([&] { return run_file_problem(file); }), "does not match the stored forged");
}

BOOST_AUTO_TEST_CASE(array_dim_campaign_and_phi_init_in_stats_h5_are_refused_not_read) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {".", "dim"}, {".", "campaign"}, {"ensembles/n64_phi0.7000_r-2.00", "phi_init"}};
  for (const auto& [object, name] : cases) {
    BOOST_TEST_CONTEXT(name) {
      const fs::path dir = kDir / name;
      fs::create_directories(dir);
      const fs::path file = dir / "stats.h5";
      jam::test::write_template_stats(file.string());
      BOOST_REQUIRE(jam::checks::read_stats(dir.string()).ensembles.size() == 1u);
      const ValueClass cls = name == "campaign" ? ValueClass::kString
                             : name == "dim"    ? ValueClass::kInteger
                                                : ValueClass::kFloat;
      Editor(file).set_attribute(object, name, cls, {4000});
      const std::string words = "attribute '" + name + "'";
      const std::string what = (object == "." ? words : words + " of '" + object + "'") +
                               " is an array of 4000, expected a scalar";
      expect_both_stats_readers(dir, what);
    }
  }
}

BOOST_AUTO_TEST_CASE(stats_h5_tables_of_the_wrong_length_are_refused_not_indexed) {
  const fs::path dir = kDir / "tables";
  fs::create_directories(dir);
  const fs::path file = dir / "stats.h5";
  jam::test::write_template_stats(file.string(), 4, 5);
  // 4 samples x 5 points would be 20 values: 23 leave a partial row past the end.
  Editor(file).set_doubles("ensembles/n64_phi0.7000_r-2.00/constant_phi/pressure_samples",
                           std::vector<double>(23, 1.0));
  expect(isolated([&] {
           jam::checks::read_stats(dir.string());
           return std::string();
         }),
         "pressure_samples' has 23 values, expected 20");
}

BOOST_AUTO_TEST_CASE(stats_h5_sample_ids_that_are_not_sample_numbers_are_refused) {
  // A fraction would be truncated onto another sample's number, NaN converts to an undefined
  // integer: both readers (the checks' and `jam stats --refit`'s) refuse the value by name.
  const std::vector<std::pair<double, std::string>> cases = {{1.5, "1.5"}, {NAN, "nan"}};
  for (const auto& [bad, shown] : cases) {
    BOOST_TEST_CONTEXT(shown) {
      const fs::path dir = kDir / ("ids-" + shown);
      fs::create_directories(dir);
      const fs::path file = dir / "stats.h5";
      jam::test::write_template_stats(file.string(), 4, 5);
      Editor(file).set_doubles("ensembles/n64_phi0.7000_r-2.00/constant_phi/sample_ids",
                               {0.0, bad, 2.0, 3.0});
      const std::string what =
          "dataset 'ensembles/n64_phi0.7000_r-2.00/constant_phi/sample_ids'"
          " holds " +
          shown + ", not a whole number";
      expect_both_stats_readers(dir, what);
    }
  }
}

BOOST_AUTO_TEST_CASE(stats_h5_constant_z_rows_of_other_samples_are_refused) {
  // The checks read a run's constant-phi and constant-Z rows as one sample: a constant-Z table
  // in another order (or of other samples) is refused, not paired with the wrong runs.
  for (const std::vector<double>& ids : {std::vector<double>{1, 0, 2, 3}, {0, 1, 2, 7}}) {
    const fs::path dir = kDir / ("z-ids-" + std::to_string(static_cast<int>(ids[0] + ids[3])));
    fs::create_directories(dir);
    const fs::path file = dir / "stats.h5";
    jam::test::write_template_stats(file.string(), 4, 5);
    Editor(file).set_doubles("ensembles/n64_phi0.7000_r-2.00/constant_z/sample_ids", ids);
    expect_checks_stats_reader(
        dir,
        "dataset 'ensembles/n64_phi0.7000_r-2.00/constant_z/sample_ids' does not list the "
        "samples of 'ensembles/n64_phi0.7000_r-2.00/constant_phi/sample_ids' in their order");
  }
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_mismatched_points_lengths_is_refused) {
  const fs::path file = forged_checkpoint(
      "points.h5", [](Editor& e) { e.set_doubles("points_pressure", std::vector<double>(4000)); });
  expect(isolated([&] { return read_checkpoint(file); }),
         "dataset 'points_pressure' has 4000 values, expected 3");
  const fs::path stress = forged_checkpoint(
      "stress.h5", [](Editor& e) { e.set_doubles("points_stress", std::vector<double>(5)); });
  expect(isolated([&] { return read_checkpoint(stress); }),
         "dataset 'points_stress' has 5 values, expected 12");
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_negative_next_output_is_refused) {
  const fs::path file =
      forged_checkpoint("next_output.h5", [](Editor& e) { e.set_int("next_output", -5); });
  expect(isolated([&] { return read_checkpoint(file); }),
         "attribute 'next_output' = -5 is outside [0, 1000000]");
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_short_per_particle_fields_is_refused) {
  const fs::path velocity = forged_checkpoint(
      "velocity.h5", [](Editor& e) { e.set_doubles("stepper_velocity_0", {1.0}); });
  expect(isolated([&] { return read_checkpoint(velocity); }),
         "dataset 'stepper_velocity_0' has 1 values, expected 8");
  const fs::path saved =
      forged_checkpoint("saved.h5", [](Editor& e) { e.set_doubles("saved_s", {0.5}); });
  expect(isolated([&] { return read_checkpoint(saved); }),
         "dataset 'saved_s' has 1 values, expected 48");
  const fs::path type = forged_checkpoint(
      "type.h5", [](Editor& e) { e.set_dataset("type", ValueClass::kInteger, {3}); });
  expect(isolated([&] { return read_checkpoint(type); }),
         "dataset 'type' has 3 values, expected 8");
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_forged_jamming_answers_is_refused) {
  // A stopped jamming-point search replays these decisions: each must be 0 or 1, and a search
  // takes far fewer than 256.
  const fs::path many = forged_checkpoint("answers-many.h5", [](Editor& e) {
    e.set_dataset("jamming_answers", ValueClass::kInteger, {300});
  });
  expect(isolated([&] { return read_checkpoint(many); }),
         "dataset 'jamming_answers' has 300 values, expected at most 256");
  const fs::path two = forged_checkpoint("answers-two.h5", [](Editor& e) {
    const std::int64_t values[2] = {0, 2};
    e.set_dataset("jamming_answers", ValueClass::kInteger, {2},
                  std::string(reinterpret_cast<const char*>(values), sizeof values));
  });
  expect(isolated([&] { return read_checkpoint(two); }),
         "dataset 'jamming_answers' holds 2, not 0 or 1");
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_forged_kept_configurations_is_refused) {
  // The search keeps one bracket of saved configurations (at least its two ends) and releases
  // the rest; saved_s holds the kept ones only, so the flags decide where each one starts.
  const std::pair<std::array<std::int64_t, 4>, const char*> cases[] = {
      {{0, 2, 1, 1}, "dataset 'saved_kept' holds 2, not 0 or 1"},
      {{1, 0, 1, 1},
       "dataset 'saved_kept' keeps 3 of 4 configurations, not one bracket of at least 2"},
      {{0, 0, 0, 1},
       "dataset 'saved_kept' keeps 1 of 4 configurations, not one bracket of at least 2"}};
  for (const auto& [values, message] : cases) {
    const std::string bytes(reinterpret_cast<const char*>(values.data()), sizeof values);
    const fs::path file = forged_checkpoint("kept.h5", [&](Editor& e) {
      e.set_dataset("saved_kept", ValueClass::kInteger, {4}, bytes);
    });
    expect(isolated([&] { return read_checkpoint(file); }), message);
  }
  const fs::path longer = forged_checkpoint(
      "kept-long.h5", [](Editor& e) { e.set_dataset("saved_kept", ValueClass::kInteger, {5}); });
  expect(isolated([&] { return read_checkpoint(longer); }),
         "dataset 'saved_kept' has 5 values, expected 4");
}

BOOST_AUTO_TEST_CASE(sealed_checkpoint_with_negative_cpu_seconds_is_refused) {
  // A resumed run adds them to its record's cost: a negative or NaN one would corrupt it.
  const fs::path file =
      forged_checkpoint("cpu.h5", [](Editor& e) { e.set_double("cpu_seconds", -3.0); });
  expect(isolated([&] { return read_checkpoint(file); }),
         "attribute 'cpu_seconds' = -3 is negative");
  const fs::path nan =
      forged_checkpoint("cpu-nan.h5", [](Editor& e) { e.set_double("cpu_seconds", std::nan("")); });
  expect(isolated([&] { return read_checkpoint(nan); }),
         "attribute 'cpu_seconds' = nan is not finite");
}

BOOST_AUTO_TEST_CASE(chained_start_with_array_identity_is_refused_not_read) {
  const fs::path file = kDir / "start.h5";
  jam::test::write_template_start(file.string(), kIdentity);
  BOOST_REQUIRE(jam::chain_start_problem(file.string(), kIdentity).empty());
  Editor(file).set_attribute(".", "identity", ValueClass::kString, {4000});
  jam::seal_file(file.string());
  const std::string what = "attribute 'identity' is an array of 4000, expected a scalar";
  expect(isolated([&] { return jam::chain_start_problem(file.string(), kIdentity); }), what);
  expect(isolated([&] {
           jam::read_chain_start<2>(file.string(), "");
           return std::string();
         }),
         what);
}

BOOST_AUTO_TEST_CASE(flipped_dimension_in_run_file_is_corrupt_without_allocating) {
  const fs::path file = valid_run_file("dimension.h5");
  // Bit 27 of the length: 2^27 more doubles, a gigabyte the old reader zero-filled.
  BOOST_REQUIRE(jam::test::flip_dimension(file, "pressure", 5, 27));
  const Isolated r = isolated([&] { return run_file_problem(file); });
  expect(r, "corrupt");
  BOOST_TEST(r.message.find("do not fit in the file") != std::string::npos, r.message);
  BOOST_TEST(r.grown_megabytes < 64);
}

BOOST_AUTO_TEST_CASE(root_group_containing_itself_is_corrupt_not_walked_for_ever) {
  const fs::path file = valid_run_file("loop.h5");
  Editor(file).link("/", "/loop");
  const Isolated r = isolated([&] { return run_file_problem(file); }, 30);
  expect(r, "an object reached twice (a loop of links");
  BOOST_TEST(r.grown_megabytes < 64);
}

BOOST_AUTO_TEST_CASE(unwritten_chunked_dataset_is_corrupt_without_allocating) {
  const fs::path file = valid_run_file("unwritten.h5");
  Editor(file).add_unwritten("extra", 300'000'000);
  const Isolated r = isolated([&] { return run_file_problem(file); });
  expect(r, "300000000 values declared but never written");
  BOOST_TEST(r.grown_megabytes < 64);
}

BOOST_AUTO_TEST_CASE(fifo_named_like_a_run_file_is_refused_before_it_is_opened) {
  const fs::path fifo = kDir / "pending.h5";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  expect(isolated([&] { return run_file_problem(fifo); }, 20),
         "HDF5 file " + fifo.string() + ": is a FIFO; only a regular file can be read");
  expect(isolated(
             [&] {
               jam::h5::File::open_read(fifo.string());
               return std::string();
             },
             20),
         "is a FIFO");
}

BOOST_AUTO_TEST_CASE(fifo_checkpoint_is_refused_before_it_is_opened) {
  const fs::path fifo = kDir / "run.h5.checkpoint";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  expect(isolated([&] { return read_checkpoint(fifo); }, 20),
         "is a FIFO; only a regular file can be read");
  expect(isolated([&] { return jam::sealed_file_problem(fifo.string()); }, 20), "is a FIFO");
}

BOOST_AUTO_TEST_CASE(fifo_read_start_is_refused_before_it_is_opened) {
  const fs::path fifo = kDir / "start-fifo.h5";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  expect(isolated([&] { return jam::chain_start_problem(fifo.string(), kIdentity); }, 20),
         "is a FIFO");
  expect(isolated([&] { return jam::stored_chain_start_identity(fifo.string()); }, 20),
         "is a FIFO");
}

BOOST_AUTO_TEST_CASE(external_link_to_a_fifo_in_stats_h5_is_not_followed) {
  const fs::path dir = kDir / "external";
  fs::create_directories(dir);
  const fs::path file = dir / "stats.h5", fifo = kDir / "elsewhere.h5";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  jam::test::write_template_stats(file.string());
  const std::string grid = "ensembles/n64_phi0.7000_r-2.00/constant_phi/packing_fraction";
  {
    Editor e(file);
    H5Ldelete(e.id(), grid.c_str(), H5P_DEFAULT);
    BOOST_REQUIRE(H5Lcreate_external(fifo.c_str(), "/x", e.id(), grid.c_str(), H5P_DEFAULT,
                                     H5P_DEFAULT) >= 0);
  }
  expect(isolated(
             [&] {
               jam::checks::read_stats(dir.string());
               return std::string();
             },
             20),
         "dataset '" + grid + "' is an external link to another file, not followed");
}

BOOST_AUTO_TEST_CASE(dataset_stored_in_a_fifo_is_refused_not_read) {
  // External storage names another file for a dataset's values; a FIFO there would block
  // the read (or the checksum walk) for ever. Both refuse it by name, at once.
  const fs::path fifo = kDir / "values.bin";
  BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const fs::path dir = kDir / "external-storage";
  fs::create_directories(dir);
  const fs::path stats = dir / "stats.h5";
  jam::test::write_template_stats(stats.string());
  const std::string grid = "ensembles/n64_phi0.7000_r-2.00/constant_phi/packing_fraction";
  Editor(stats).add_external(grid, 5, fifo.string());
  expect(isolated(
             [&] {
               jam::checks::read_stats(dir.string());
               return std::string();
             },
             20),
         "dataset '" + grid + "' keeps its values in another file");
  const fs::path run = valid_run_file("external-storage.h5");
  Editor(run).add_external("extra", 5, fifo.string());
  expect(isolated([&] { return run_file_problem(run); }, 20),
         "keeps its values in another file, not written by jam");
}

BOOST_AUTO_TEST_CASE(valid_files_still_read_and_verify) {
  const fs::path file = valid_run_file("valid.h5");
  const auto check = jam::check_run_file(file.string());
  BOOST_TEST(check.problem.empty(), check.problem);
  BOOST_TEST(check.verified);
  const fs::path checkpoint = kDir / "valid.checkpoint";
  jam::test::write_template_checkpoint(checkpoint.string(), kFingerprint);
  const auto c = jam::read_checkpoint<2>(checkpoint.string(), kFingerprint);
  BOOST_REQUIRE(c.has_value());
  BOOST_TEST(c->state.points.size() == 3u);
  BOOST_TEST_REQUIRE(c->state.saved.size() == 4u);
  BOOST_TEST(c->state.saved[0].s.empty());  // released by the search
  BOOST_TEST(c->state.saved[1].s.size() == 16u);
  BOOST_TEST(c->state.saved[3].packing_fraction == 0.73);
  BOOST_TEST((c->state.jamming_answers == jam::JammingAnswers{0, 1, 1}));
  BOOST_TEST(c->state.cpu_seconds == 12.5);
  BOOST_TEST(c->stepper.size() == 3u);
}

BOOST_AUTO_TEST_SUITE_END()
