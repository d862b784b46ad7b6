// libFuzzer target: the run-file reader (check_run_file, run_identity_problem) on a valid run
// file edited by a recipe of shapes and classes (hdf5_recipe.hpp), with its checksum forged
// after the edits when the recipe asks, so that the reader's shape checks are reached too.
// Neither may throw (they return the problem), crash or read more than the file holds.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "hdf5_recipe.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/run_file.hpp"
#include "sim/run/compression_run.hpp"

namespace {

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "complete"},
    {".", "checksum"},
    {".", "data_checksum"},
    {".", "fingerprint"},
    {".", "schema_version"},
    {".", "dim"},
    {".", "n"},
    {".", "seed"},
    {".", "phi_init"},
    {".", "compression_rate"},
    {".", "integrator"},
    {"", "packing_fraction"},
    {"", "pressure"},
    {"", "contacts_per_particle"},
    {"", "energy_per_particle"},
    {"", "time"},
    {"", "contacts_per_particle_no_rattlers"},
    {"", "rattler_fraction"},
    {"", "stress"},
};

// N = 16 in 2D with rattlers and stress, so that every dataset of the schema is there.
jam::SimConfig template_run() {
  jam::SimConfig c;
  c.n = 16;
  c.phi_init = 0.7;
  c.phi_stop = 0.72;
  c.phi_step = 0.005;
  c.compression_rate = 1e-2;
  c.rattlers = true;
  c.stress = true;
  c.quiet = true;
  c.checkpoint_interval = 0;
  c.out = (std::filesystem::temp_directory_path() /
           ("jam-fuzz-run-template-" + std::to_string(::getpid()) + ".h5"))
              .string();
  return c;
}

const std::string& template_bytes() {
  static const std::string bytes = [] {
    const jam::SimConfig c = template_run();
    jam::run_compression(c);
    std::string b = jam::test::file_bytes(c.out);
    std::filesystem::remove(c.out);
    return b;
  }();
  return bytes;
}

/// Stores the checksum of what the file now holds, as a forger would.
void forge_checksum(const std::filesystem::path& path) {
  std::string text;
  try {
    text = jam::checksum_text(
        jam::content_checksum(jam::h5::File::open_read(path.string()), {"checksum"}));
  } catch (const std::exception&) {
    return;  // the walk itself refuses the file: nothing to forge
  }
  jam::test::Editor(path).set_attribute(".", "checksum", jam::test::ValueClass::kString, {}, text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const jam::fuzz::Recipe recipe(data, size);
  const auto path = jam::fuzz::prepare("jam-fuzz-run-file", template_bytes(), recipe, kTargets);
  if (recipe.forge()) forge_checksum(path);
  jam::check_run_file(path.string());
  jam::run_identity_problem(path.string(), template_run());
  std::filesystem::remove(path);
  return 0;
}
