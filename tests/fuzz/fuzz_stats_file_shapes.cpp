// libFuzzer target: the stats.h5 readers (jam check's read_stats, jam stats --refit's
// refit_campaign_stats without the fit) on a valid stats.h5 edited by a recipe of shapes and
// classes (hdf5_recipe.hpp). The template carries no checksum (a stats.h5 without one is read
// unsealed), so the schema (reference/schema/stats.toml) and the readers' shape checks are all
// there is. They may throw std::exception; nothing may crash or allocate beyond the file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "checks/stats_data.hpp"
#include "hdf5_recipe.hpp"
#include "stats/campaign_stats.hpp"

namespace {

const std::string kEnsemble = "ensembles/n64_phi0.7000_r-2.00";

const std::vector<jam::fuzz::Target> kTargets = {
    {".", "campaign"},
    {".", "dim"},
    {".", "pooled_sizes"},
    {".", "runs"},
    {".", "runs_skipped"},
    {kEnsemble, "n"},
    {kEnsemble, "phi_init"},
    {kEnsemble, "log10_rate"},
    {kEnsemble, "chain_phi_init"},
    {"fit/representative", "phi_min"},
    {"fit/representative", "phi_j"},
    {"", kEnsemble + "/constant_phi/packing_fraction"},
    {"", kEnsemble + "/constant_phi/sample_ids"},
    {"", kEnsemble + "/constant_phi/pressure_samples"},
    {"", kEnsemble + "/constant_phi/contacts_per_particle_samples"},
    {"", kEnsemble + "/constant_z/contacts_per_particle"},
    {"", kEnsemble + "/constant_z/sample_ids"},
    {"", kEnsemble + "/constant_z/pressure_samples"},
    {"", kEnsemble + "/jamming/packing_fraction_samples"},
    {"", "ensembles/extra"},
};

const std::filesystem::path kDir =
    std::filesystem::temp_directory_path() / ("jam-fuzz-stats-" + std::to_string(::getpid()));

const std::string& template_bytes() {
  static const std::string bytes = [] {
    std::filesystem::create_directories(kDir);
    const auto path = kDir / "template.h5";
    jam::test::write_template_stats(path.string());
    std::string b = jam::test::file_bytes(path);
    std::filesystem::remove(path);
    return b;
  }();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const jam::fuzz::Recipe recipe(data, size);
  const auto edited = jam::fuzz::prepare("jam-fuzz-stats", template_bytes(), recipe, kTargets);
  std::filesystem::rename(edited, kDir / "stats.h5");
  try {
    jam::checks::read_stats(kDir.string());
  } catch (const std::exception&) {
  }
  try {
    jam::stats::StatsOptions o;
    o.fit = false;
    jam::stats::refit_campaign_stats(kDir.string(), o);
  } catch (const std::exception&) {
  }
  return 0;
}
