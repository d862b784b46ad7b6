// libFuzzer target: the chained-start reader (read_chain_start, 2D; chain_start_problem;
// stored_chain_start_identity) on a valid start edited by a recipe of shapes and classes
// (hdf5_recipe.hpp) and sealed again, so that the seal is valid and only the reader's own
// checks remain. It may end in a start or CorruptCheckpoint / ForeignCheckpoint; nothing else.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "hdf5_recipe.hpp"
#include "sim/io/sealed_file.hpp"

namespace {

const std::string kIdentity = "fuzz-start";

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "identity"}, {".", "box_length"}, {".", "packing_fraction"},
    {".", "dim"},      {"", "s_0"},         {"", "s_1"},
    {"", "id"},        {"", "type"},
};

const std::string& template_bytes() {
  static const std::string bytes = [] {
    const auto path = std::filesystem::temp_directory_path() /
                      ("jam-fuzz-start-template-" + std::to_string(::getpid()) + ".h5");
    jam::test::write_template_start(path.string(), kIdentity);
    std::string b = jam::test::file_bytes(path);
    std::filesystem::remove(path);
    return b;
  }();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const jam::fuzz::Recipe recipe(data, size);
  const auto path = jam::fuzz::prepare("jam-fuzz-start", template_bytes(), recipe, kTargets);
  jam::seal_file(path.string());
  jam::chain_start_problem(path.string(), kIdentity);
  try {
    jam::stored_chain_start_identity(path.string());
    const auto s = jam::read_chain_start<2>(path.string(), "");
    const std::size_t n = s.particles.size();
    if (n == 0 || s.particles.s[0].size() != n || s.particles.s[1].size() != n ||
        !(s.box_length > 0.0 && std::isfinite(s.box_length))) {
      std::abort();
    }
  } catch (const jam::CorruptCheckpoint&) {
  } catch (const jam::ForeignCheckpoint&) {
  }
  std::filesystem::remove(path);
  return 0;
}
