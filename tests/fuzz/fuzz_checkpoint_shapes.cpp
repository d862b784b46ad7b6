// libFuzzer target: the checkpoint reader (read_checkpoint, 2D) on a valid checkpoint edited by
// a recipe of shapes and classes (hdf5_recipe.hpp) and sealed again: a forged but valid seal,
// so that only the reader's shape checks stand between the edits and a resumed run. The reader
// may only end in a checkpoint whose sizes a run can rely on, or in CorruptCheckpoint /
// ForeignCheckpoint; anything else escaping, or a sanitizer report, is a failure.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "hdf5_recipe.hpp"
#include "sim/io/sealed_file.hpp"

namespace {

const std::string kFingerprint = "fuzz-checkpoint";

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "fingerprint"},
    {".", "phase"},
    {".", "relax_steps"},
    {".", "steps"},
    {".", "next_output"},
    {".", "time"},
    {".", "relax_time"},
    {".", "stepper_fields"},
    {".", "stepper_field_0"},
    {".", "stepper_field_2"},
    {"", "s_0"},
    {"", "s_1"},
    {"", "id"},
    {"", "type"},
    {"", "points_time"},
    {"", "points_pressure"},
    {"", "points_rattler_fraction"},
    {"", "points_stress"},
    {"", "saved_packing_fraction"},
    {"", "saved_kept"},
    {"", "saved_s"},
    {"", "stepper_velocity_0"},
    {"", "stepper_have_forces"},
};

const std::string& template_bytes() {
  static const std::string bytes = [] {
    const auto path = std::filesystem::temp_directory_path() /
                      ("jam-fuzz-checkpoint-template-" + std::to_string(::getpid()) + ".h5");
    jam::test::write_template_checkpoint(path.string(), kFingerprint);
    std::string b = jam::test::file_bytes(path);
    std::filesystem::remove(path);
    return b;
  }();
  return bytes;
}

/// What a resumed run relies on (compression_run.cpp, the integrators, the jamming point).
void check_sizes(const jam::Checkpoint<2>& c) {
  const std::size_t n = c.particles.size();
  bool ok = n > 0 && c.state.next_output >= 0 && c.state.steps >= 0;
  // Kept configurations whole, released ones empty (the search never reads those).
  for (const auto& s : c.state.saved) ok = ok && (s.s.size() == 2 * n || s.s.empty());
  for (const auto& [name, values] : c.stepper)
    ok = ok && (values.size() == n || values.size() == 1);
  for (int d = 0; d < 2; ++d) {
    ok = ok && c.particles.s[d].size() == n;
    for (double s : c.particles.s[d]) ok = ok && s >= 0.0 && s < 1.0;
  }
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const jam::fuzz::Recipe recipe(data, size);
  const auto path = jam::fuzz::prepare("jam-fuzz-checkpoint", template_bytes(), recipe, kTargets);
  jam::seal_file(path.string());
  try {
    if (const auto c = jam::read_checkpoint<2>(path.string(), kFingerprint)) check_sizes(*c);
  } catch (const jam::CorruptCheckpoint&) {
  } catch (const jam::ForeignCheckpoint&) {
  }
  std::filesystem::remove(path);
  return 0;
}
