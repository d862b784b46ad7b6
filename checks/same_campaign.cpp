#include "checks/same_campaign.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "sim/io/hdf5_file.hpp"
#include "sim/io/open_run.hpp"

namespace jam::checks {
namespace {

namespace fs = std::filesystem;

/// The content of each run file in DIR/runs, by its signature: a run file of jam's own by the
/// checksum over its content it carries (a copy keeps it), any other by the checksum of its
/// bytes (an import copies them). Files that do not open are left to the statistics to name.
std::map<std::string, std::string> run_signatures(const std::string& directory) {
  std::map<std::string, std::string> out;
  std::error_code ec;
  const fs::path runs = fs::path(directory) / "runs";
  if (directory.empty() || !fs::is_directory(runs, ec)) return out;
  for (const auto& entry : fs::directory_iterator(runs, ec)) {
    if (!entry.is_regular_file(ec) || entry.path().extension() != ".h5") continue;
    try {
      const std::string path = entry.path().string();
      const h5::File f = h5::File::open_read(path);
      const std::string signature = f.has_attribute("checksum")
                                        ? "content " + f.read_attribute_string("checksum")
                                        : "bytes " + file_checksum(path);
      out.emplace(signature, entry.path().filename().string());
    } catch (const std::exception&) {
    }
  }
  return out;
}

/// Two rows of one run: equal (to round-off) at every grid value both grids have, at least two
/// of them with a pressure.
bool same_row(const std::vector<double>& grid_a, const std::vector<double>& a,
              const std::vector<double>& grid_b, const std::vector<double>& b) {
  std::size_t j = 0, compared = 0;
  for (std::size_t i = 0; i < grid_a.size(); ++i) {
    while (j < grid_b.size() && grid_b[j] < grid_a[i] - 1e-9) ++j;
    if (j == grid_b.size()) break;
    if (std::abs(grid_b[j] - grid_a[i]) >= 1e-9) continue;
    if (!(std::isfinite(a[i]) && std::isfinite(b[j]))) continue;
    if (std::abs(a[i] - b[j]) > 1e-9 * std::abs(b[j])) return false;
    compared += b[j] != 0.0;
  }
  return compared >= 2;
}

/// The first row of DIR's tables that is one of REF's, in words, and how many there are.
std::pair<std::string, std::size_t> shared_rows(const StatsData& dir, const StatsData& ref) {
  std::string first;
  std::size_t count = 0;
  for (const auto& d : dir.ensembles) {
    for (const auto& r : ref.ensembles) {
      if (d.n != r.n) continue;
      for (std::size_t s = 0; s < d.pressure_at_phi.size(); ++s) {
        for (std::size_t t = 0; t < r.pressure_at_phi.size(); ++t) {
          if (!same_row(d.phi_grid, d.pressure_at_phi[s], r.phi_grid, r.pressure_at_phi[t]))
            continue;
          if (count++ == 0)
            first = fmt::format("{} sample {} is REF's {} sample {}", case_label(d),
                                d.sample_ids.at(s), case_label(r), r.sample_ids.at(t));
          break;
        }
      }
    }
  }
  return {first, count};
}

}  // namespace

void refuse_same_campaign(const StatsData& dir, const StatsData& ref) {
  constexpr const char* kWhy = "a campaign compared with itself passes whatever it holds";
  std::error_code ec;
  if (!dir.directory.empty() && !ref.directory.empty() &&
      fs::equivalent(dir.directory, ref.directory, ec)) {
    throw std::runtime_error(fmt::format("compare: DIR {} and REF {} are one directory: {}",
                                         dir.directory, ref.directory, kWhy));
  }
  const auto dir_runs = run_signatures(dir.directory), ref_runs = run_signatures(ref.directory);
  std::size_t same = 0;
  std::string example;
  for (const auto& [signature, file] : dir_runs) {
    const auto it = ref_runs.find(signature);
    if (it == ref_runs.end()) continue;
    if (same++ == 0) example = fmt::format("runs/{} is REF's runs/{}", file, it->second);
  }
  if (same > 0) {
    throw std::runtime_error(fmt::format(
        "compare: DIR {} and REF {} hold the same run files ({} of DIR's {} have the content of "
        "one of REF's: {}): {}",
        dir.directory, ref.directory, same, dir_runs.size(), example, kWhy));
  }
  const auto [first, rows] = shared_rows(dir, ref);
  if (rows > 0) {
    throw std::runtime_error(fmt::format(
        "compare: DIR {} and REF {} hold the same runs ({} of DIR's runs have the pressure of "
        "one of REF's at every grid value in stats.h5: DIR's {}): {}",
        dir.directory.empty() ? "(in memory)" : dir.directory,
        ref.directory.empty() ? "(in memory)" : ref.directory, rows, first, kWhy));
  }
}

}  // namespace jam::checks
