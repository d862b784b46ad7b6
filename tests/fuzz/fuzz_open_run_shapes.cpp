// libFuzzer target: the open run reader (sim/io/open_run.hpp, read_open_run: every file jam
// imports from another simulator) on a valid open run edited by a recipe of shapes, classes and
// values (hdf5_recipe.hpp). It must return a run that passes validate_open_run or throw
// std::runtime_error; nothing else may escape, crash or read more than the file holds.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "hdf5_recipe.hpp"
#include "sim/io/open_run.hpp"

namespace {

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "format"},    {".", "format_version"},    {".", "protocol"},
    {".", "units"},     {".", "dim"},               {".", "n"},
    {".", "diameter_ratio"}, {".", "contact"},      {".", "dynamics"},
    {".", "compression_rate"}, {".", "phi_init"},   {".", "simulator"},
    {".", "simulator_version"}, {".", "sample"},    {".", "jamming_packing_fraction"},
    {"", "packing_fraction"}, {"", "pressure"},     {"", "contacts_per_particle"},
    {"", "energy_per_particle"}, {"", "time"},
};

const std::string& template_bytes() {
  static const std::string bytes = [] {
    jam::OpenRun r;
    r.dim = 2;
    r.n = 64;
    r.compression_rate = 1e-3;
    r.phi_init = 0.8;
    r.simulator = "fuzz";
    r.jamming_packing_fraction = 0.84;
    for (int k = 0; k < 8; ++k) {
      r.time.push_back(2.0 * k);
      r.packing_fraction.push_back(0.8 * std::exp(2e-3 * 2.0 * k));
      r.pressure.push_back(1e-3 * k);
      r.contacts_per_particle.push_back(0.5 * k);
      r.energy_per_particle.push_back(1e-6 * k);
    }
    const auto path = std::filesystem::temp_directory_path() /
                      ("jam-fuzz-open-run-template-" + std::to_string(::getpid()) + ".h5");
    jam::write_open_run(path.string(), r);
    std::string b = jam::test::file_bytes(path);
    std::filesystem::remove(path);
    return b;
  }();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const jam::fuzz::Recipe recipe(data, size);
  const auto path = jam::fuzz::prepare("jam-fuzz-open-run", template_bytes(), recipe, kTargets);
  try {
    const jam::OpenRun r = jam::read_open_run(path.string());
    jam::validate_open_run(r, path.string());  // what the reader returns meets the spec
  } catch (const std::runtime_error&) {
  }
  std::filesystem::remove(path);
  return 0;
}
