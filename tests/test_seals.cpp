// Everything jam resumes from or trusts is checked before use. A checkpoint or relaxed start
// with one flipped bit (in its positions, its fingerprint or its seal) is discarded with a
// warning and the run redone from scratch, bitwise as an uninterrupted run; a run file with a
// flipped bit in any attribute that gives its data meaning (compression_rate, phi_init,
// jamming_packing_fraction) fails its checksum; a run file of schema 1 (datasets-only
// checksum) stays readable, flagged as unverified.
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <boost/test/unit_test.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "file_faults.hpp"
#include "process.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/io/checkpoint.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/fnv1a.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/run_file.hpp"
#include "sim/io/sealed_file.hpp"
#include "sim/run/compression_run.hpp"

namespace fs = std::filesystem;
using jam::test::flip_bit_of;
using jam::test::slurp;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-seals-" + std::to_string(::getpid()));

struct Fixture {
  Fixture() { fs::create_directories(kDir); }
  ~Fixture() { fs::remove_all(kDir); }
};

// A run of about 0.2 s: N = 128 from 0.7 to 0.8 at rate 1e-2.5, output every 0.005.
jam::SimConfig small_run(const std::string& name) {
  jam::SimConfig c;
  c.n = 128;
  c.phi_init = 0.7;
  c.phi_stop = 0.8;
  c.phi_step = 0.005;
  c.compression_rate = 3e-3;
  c.seed = 11;
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.relax_energy = "1e-10";  // one relaxed start for every rate (the start cache's key)
  c.out = (kDir / name).string();
  return c;
}

/// Runs c until its first checkpoint opportunity (a stop requested before it starts), leaving
/// the checkpoint on disk.
void interrupt_early(const jam::SimConfig& c) {
  const std::atomic<bool> stop{true};
  jam::RunControl control;
  control.checkpoint_interval_seconds = 0;
  control.stop = &stop;
  BOOST_REQUIRE(jam::run_compression(c, control).interrupted);
  BOOST_REQUIRE(fs::exists(jam::checkpoint_path(c.out)));
}

}  // namespace

BOOST_FIXTURE_TEST_SUITE(seals, Fixture)

BOOST_AUTO_TEST_CASE(damaged_checkpoint_is_never_resumed) {
  const jam::SimConfig reference = small_run("reference.h5");
  jam::run_compression(reference);
  const std::string expected = slurp(reference.out);

  // Three kinds of damage: a position, the fingerprint's text, the seal itself.
  for (int damage = 0; damage < 3; ++damage) {
    BOOST_TEST_CONTEXT("damage " << damage) {
      const jam::SimConfig c = small_run("resumed.h5");
      fs::remove(c.out);
      interrupt_early(c);
      const std::string checkpoint = jam::checkpoint_path(c.out);
      BOOST_REQUIRE(jam::sealed_file_problem(checkpoint) == "");
      const auto saved = jam::read_checkpoint<2>(checkpoint, jam::fingerprint(c));
      BOOST_REQUIRE(saved.has_value());
      if (damage == 0) BOOST_REQUIRE(flip_bit_of(checkpoint, saved->particles.s[0][17]));
      if (damage == 1) BOOST_REQUIRE(jam::test::flip_bit_of_text(checkpoint, "seed=11"));
      if (damage == 2) BOOST_REQUIRE(jam::test::flip_bit_of_text(checkpoint, "jam-seal fnv1a64 "));
      BOOST_TEST(jam::sealed_file_problem(checkpoint) != "");
      BOOST_CHECK_THROW(jam::read_checkpoint<2>(checkpoint, jam::fingerprint(c)),
                        jam::CorruptCheckpoint);
      // The run discards it and starts afresh: the same bits as never interrupted.
      const jam::RunSummary s = jam::run_compression(c);
      BOOST_TEST(!s.resumed);
      BOOST_TEST((slurp(c.out) == expected));
      BOOST_TEST(!fs::exists(checkpoint));
    }
  }
}

BOOST_AUTO_TEST_CASE(sound_checkpoint_is_resumed) {
  const jam::SimConfig reference = small_run("reference.h5");
  jam::run_compression(reference);
  const jam::SimConfig c = small_run("resumed.h5");
  interrupt_early(c);
  const jam::RunSummary s = jam::run_compression(c);
  BOOST_TEST(s.resumed);
  BOOST_TEST((slurp(c.out) == slurp(reference.out)));
}

// A relaxed start shared by the rates of a sample: damaged, it is replaced, not used.
BOOST_AUTO_TEST_CASE(damaged_start_cache_is_replaced) {
  jam::SimConfig fresh = small_run("fresh.h5");
  fresh.compression_rate = 1e-2;
  jam::run_compression(fresh);
  jam::SimConfig first = small_run("first.h5");
  first.start_cache = (kDir / "start.h5").string();
  jam::run_compression(first);
  BOOST_REQUIRE(jam::sealed_file_problem(first.start_cache) == "");
  const auto start = jam::read_checkpoint<2>(first.start_cache, jam::relaxation_fingerprint(first));
  BOOST_REQUIRE(flip_bit_of(first.start_cache, start->particles.s[1][5]));

  jam::SimConfig second = fresh;
  second.out = (kDir / "second.h5").string();
  second.start_cache = first.start_cache;
  jam::run_compression(second);
  BOOST_TEST((slurp(second.out) == slurp(fresh.out)));  // relaxed afresh, not from the damage
  BOOST_TEST(jam::sealed_file_problem(first.start_cache) == "");  // rewritten sound
}

BOOST_AUTO_TEST_CASE(run_file_attributes_are_covered) {
  jam::SimConfig c = small_run("run.h5");
  c.compression_rate = 0.0123;  // a value found nowhere else in the file
  c.phi_stop = 0.9;
  c.jamming_point = true;
  c.jamming_search_from = 0.8;
  jam::run_compression(c);
  BOOST_REQUIRE(jam::run_file_problem(c.out) == "");
  BOOST_TEST(jam::check_run_file(c.out).verified);
  const std::string pristine = slurp(c.out);
  double phi_init = 0, phi_j = 0, phi0 = 0;
  {
    const auto f = jam::h5::File::open_read(c.out);
    phi_init = f.read_attribute_double("phi_init");
    phi_j = f.read_attribute_double("jamming_packing_fraction");
    phi0 = f.read_dataset("packing_fraction")[0];
  }
  for (const double value : {0.0123, phi_init, phi_j}) {
    BOOST_TEST_CONTEXT("attribute value " << value) {
      std::ofstream(c.out, std::ios::binary | std::ios::trunc) << pristine;
      BOOST_REQUIRE(flip_bit_of(c.out, value));
      // The flip landed in the attribute (read back changed), not in a dataset.
      BOOST_TEST(jam::h5::File::open_read(c.out).read_dataset("packing_fraction")[0] == phi0);
      BOOST_TEST(jam::run_file_problem(c.out).find("checksum") != std::string::npos);
    }
  }
}

// A run file as written before schema 2: datasets and a datasets-only checksum, computed here
// independently (FNV-1a 64 over each dataset's name and values, in the schema's order).
BOOST_AUTO_TEST_CASE(schema_1_files_read_unverified) {
  const std::string path = (kDir / "old.h5").string();
  const std::vector<double> phi = {0.70, 0.71, 0.72}, p = {1e-3, 2e-3, 3e-3}, z = {3, 3.5, 4};
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto add = [&h](const void* data, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) {
      h ^= static_cast<const unsigned char*>(data)[k];
      h *= 0x100000001b3ULL;
    }
  };
  for (const auto& [name, v] : {std::pair{"packing_fraction", phi}, std::pair{"pressure", p},
                                std::pair{"contacts_per_particle", z}}) {
    add(name, std::strlen(name));
    add(v.data(), v.size() * sizeof(double));
  }
  {
    auto f = jam::h5::File::create(path);
    f.write_dataset("packing_fraction", phi);
    f.write_dataset("pressure", p);
    f.write_dataset("contacts_per_particle", z);
    f.write_attribute("data_checksum", fmt::format("{:016x}", h));
    f.write_attribute("complete", std::int64_t{1});
    f.close();
  }
  const jam::RunFileCheck check = jam::check_run_file(path);
  BOOST_TEST(check.problem == "");
  BOOST_TEST(!check.verified);
  BOOST_REQUIRE(flip_bit_of(path, 2e-3));
  BOOST_TEST(jam::run_file_problem(path).find("data checksum") != std::string::npos);
}

// Every hash jam stores goes through one accumulator (sim/io/fnv1a.hpp): FNV-1a 64 as
// published (the test vectors of its authors), and the stored files of the repository still
// verify, so that a change to the accumulator cannot pass unnoticed by changing writer and
// reader together.
BOOST_AUTO_TEST_CASE(one_hash_for_every_stored_checksum) {
  auto of = [](std::string_view s) {
    jam::Fnv1a h;
    h.add(s);
    return h.hex();
  };
  BOOST_TEST(of("") == "cbf29ce484222325");
  BOOST_TEST(of("a") == "af63dc4c8601ec8c");
  BOOST_TEST(of("foobar") == "85944171f73967e8");
  jam::Fnv1a sized;
  sized.add_sized("foobar");  // the length as 8 bytes (little-endian here), then the text
  BOOST_TEST(sized.hex() == "b277229a2d9d19f2");
  BOOST_TEST(jam::checksum_text(jam::bytes_checksum("foobar")) == "85944171f73967e8");
  BOOST_TEST(jam::chain_start_key("parent at packing 0.5") == "2238acc1b1b74878");
  const std::string text = (kDir / "foobar.txt").string();
  std::ofstream(text) << "foobar";
  BOOST_TEST(jam::file_checksum(text) == "85944171f73967e8");
  // Sealed starts and checkpoints (jam-seal fnv1a64), a run file's content checksum.
  const fs::path source = JAM_SOURCE_DIR;
  BOOST_TEST(jam::sealed_file_problem(
                 (source / "tests/fuzz/corpus/checkpoint/checkpoint-2d.h5").string()) == "");
  BOOST_TEST(jam::sealed_file_problem(
                 (source / "tests/fuzz/corpus/checkpoint/start-3d.h5").string()) == "");
  BOOST_TEST(
      jam::run_file_problem(
          (source / "reference/results/paper-2d-convergence/runs/n16384_phi0.4000_r-8.00_s000.h5")
              .string()) == "");
}

BOOST_AUTO_TEST_SUITE_END()
