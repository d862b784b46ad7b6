// libFuzzer target: the import path (campaign/external_import.cpp) on a recipe of files, values
// and interleavings. Three open runs (samples 0, 1, 2 of one ensemble), each edited by its own
// third of the input as hdf5_recipe.hpp edits a file; byte 0 chooses the interleaving: all at
// once or one by one, a file of someone's in runs/ before the first import, a stored copy
// damaged between imports, every file imported again. Whatever the recipe:
//   - an import ends in an outcome or a std::exception naming the problem, nothing else;
//   - a campaign an import wrote reads back (external.toml), and every run it lists has its
//     stored copy, which reads as an open run with its checksum unless this recipe damaged it
//     after the last import;
//   - a file in runs/ that external.toml does not list is never changed.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../open_run_fixture.hpp"
#include "campaign/external_campaign.hpp"
#include "hdf5_recipe.hpp"
#include "sim/io/open_run.hpp"

namespace fs = std::filesystem;

namespace {

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "n"},       {".", "sample"},          {".", "phi_init"},  {".", "compression_rate"},
    {".", "dim"},     {".", "dynamics"},        {".", "simulator"}, {".", "diameter_ratio"},
    {"", "pressure"}, {"", "packing_fraction"}, {"", "time"},       {"", "contacts_per_particle"},
};

const std::string& template_bytes(int sample) {
  static std::vector<std::string> bytes = [] {
    std::vector<std::string> out;
    for (int s = 0; s < 3; ++s) {
      jam::OpenRun r = jam::test::open_run_of(64, 1e-3, 0.8, s, "fuzz");
      for (int k = 0; k < 8; ++k) {
        r.time.push_back(2.0 * k);
        r.packing_fraction.push_back(0.8 * std::exp(2e-3 * 2.0 * k));
        r.pressure.push_back(1e-3 * k * (1 + 0.1 * s));
        r.contacts_per_particle.push_back(0.5 * k);
      }
      const auto path = fs::temp_directory_path() /
                        ("jam-fuzz-import-template-" + std::to_string(::getpid()) + ".h5");
      jam::write_open_run(path.string(), r);
      out.push_back(jam::test::file_bytes(path));
      fs::remove(path);
    }
    return out;
  }();
  return bytes[static_cast<std::size_t>(sample)];
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void import(const fs::path& dir, const std::vector<std::string>& files) {
  try {
    jam::import_runs(dir.string(), files, {});
  } catch (const std::exception&) {
    // A refusal: one error naming the problem (what it says is the reader's tests' concern).
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::uint8_t plan = size > 0 ? data[0] : 0;
  const fs::path root =
      fs::temp_directory_path() / ("jam-fuzz-import-" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "sources");
  const fs::path dir = root / "campaign";
  // Three files, each edited by its third of the input after byte 0.
  std::vector<std::string> files;
  const std::size_t third = size > 1 ? (size - 1) / 3 : 0;
  for (int s = 0; s < 3; ++s) {
    const jam::fuzz::Recipe recipe(data + 1 + s * third, third);
    const fs::path edited = jam::fuzz::prepare("jam-fuzz-import-" + std::to_string(s),
                                               template_bytes(s), recipe, kTargets);
    const fs::path source = root / "sources" / ("s" + std::to_string(s) + ".h5");
    fs::rename(edited, source);
    files.push_back(source.string());
  }
  // Someone's file in runs/ at a run's name, before any import.
  const fs::path theirs = dir / "runs" / "n64_phi0.8000_r-3.00_s001.h5";
  if (plan & 1) {
    fs::create_directories(theirs.parent_path());
    std::ofstream(theirs) << "someone's notes";
  }
  if (plan & 2) {
    import(dir, files);
  } else {
    for (const auto& f : files) import(dir, {f});
  }
  if (plan & 4) {  // a stored copy damaged between imports
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir / "runs", ec))
      if (e.path() != theirs) {
        fs::resize_file(e.path(), fs::file_size(e.path()) / 2, ec);
        break;
      }
  }
  if (plan & 8) import(dir, files);  // every file again: repairs what it can
  if ((plan & 1) && slurp(theirs) != "someone's notes") std::abort();  // never replaced
  if (jam::is_external_campaign(dir.string())) {
    const jam::ExternalCampaign c = jam::read_external_campaign(dir.string());  // must read
    for (const auto& run : c.runs) {
      if (!fs::exists(dir / "runs" / (run.name + ".h5"))) std::abort();  // listed, not stored
      const bool damaged_since = (plan & 4) && !(plan & 8);
      if (!damaged_since && !jam::stored_run_problem(dir.string(), run).empty()) std::abort();
    }
  }
  fs::remove_all(root);
  return 0;
}
