// Reading the averages back from a stats.h5 (refit_campaign_stats in campaign_stats.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "sim/io/hdf5_file.hpp"
#include "stats/campaign_stats.hpp"
#include "stats/sample_ids.hpp"
#include "stats/stats_inputs.hpp"
#include "stats/stats_schema.hpp"

namespace jam::stats {
namespace {

/// One averaging of an ensemble: its grid, sample ids and per-sample tables.
GridAverage read_average(const h5::File& f, const std::string& group, const std::string& grid) {
  GridAverage a;
  a.grid_name = grid;
  a.grid = f.read_dataset(group + "/" + grid);
  a.sample_ids = read_sample_ids(f, group);
  const std::size_t m = a.grid.size();
  for (const auto& name : f.list_group(group)) {
    const auto at = name.rfind("_samples");
    if (at == std::string::npos || at + 8 != name.size()) continue;
    // One row per sample, one column per grid point: the tables are indexed so.
    const auto flat = f.read_dataset(group + "/" + name, h5::exactly(a.sample_ids.size() * m));
    std::vector<std::vector<double>> rows;
    for (std::size_t s = 0; m > 0 && (s + 1) * m <= flat.size(); ++s) {
      rows.emplace_back(flat.begin() + static_cast<long>(s * m),
                        flat.begin() + static_cast<long>((s + 1) * m));
    }
    a.names.push_back(name.substr(0, at));
    a.tables.push_back(std::move(rows));
  }
  finalize(a);
  return a;
}

/// The grid a constant-Z group names: with rattlers or without.
std::string z_grid_name(const h5::File& f, const std::string& group) {
  const auto names = f.list_group(group);
  return std::find(names.begin(), names.end(), std::string("contacts_per_particle_no_rattlers")) !=
                 names.end()
             ? "contacts_per_particle_no_rattlers"
             : "contacts_per_particle";
}

/// ensembles/<name>/coverage/, carried over as it was stored (run_coverage.hpp).
RunCoverage read_coverage(const h5::File& f, const std::string& group) {
  RunCoverage c;
  c.sample_ids = read_sample_ids(f, group);
  const auto rows = h5::exactly(c.sample_ids.size());
  c.phi_last = f.read_dataset(group + "/packing_fraction_last", rows);
  c.output_step = f.read_dataset(group + "/packing_fraction_step", rows);
  if (f.has_dataset(group + "/constant_phi"))
    c.constant_phi = read_average(f, group + "/constant_phi", "packing_fraction");
  if (f.has_dataset(group + "/constant_z"))
    c.constant_z = read_average(f, group + "/constant_z", z_grid_name(f, group + "/constant_z"));
  return c;
}

}  // namespace

CampaignStats refit_campaign_stats(const std::string& directory, const StatsOptions& o) {
  const std::string path = (std::filesystem::path(directory) / "stats.h5").string();
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error(fmt::format("{}: no stats.h5 to refit", directory));
  }
  CampaignStats s;
  // Where the averages came from, without this machine's path.
  s.refit_from = "the averages of an earlier stats.h5 (jam stats --refit)";
  {
    const h5::File f = h5::File::open_read(path);
    check_stats_checksum(f, directory);
    check_stats_schema(f);  // reference/schema/stats.toml, as jamio checks it
    s.data.name = f.read_attribute_string("campaign");
    // The averages are the earlier file's: so are the runs they were computed from.
    if (f.has_attribute("inputs_checksum"))
      s.inputs_checksum = f.read_attribute_string("inputs_checksum");
    const std::int64_t dim = f.read_attribute_int("dim");
    if (dim != 2 && dim != 3) {
      throw std::runtime_error(fmt::format("{}: attribute 'dim' = {}, expected 2 or 3", path, dim));
    }
    s.data.dim = static_cast<int>(dim);
    s.runs_averaged = f.read_attribute_int("runs");
    s.runs_skipped = f.read_attribute_int("runs_skipped");
    // Carried over for readers of the new file; unknown (not written) when the old one lacks it.
    s.data.phi_step =
        f.has_attribute("phi_step") ? f.read_attribute_double("phi_step") : std::nan("");
    for (const auto& name : f.list_group("ensembles")) {
      const std::string g = "ensembles/" + name;
      EnsembleStats e;
      e.key = {f.read_attribute_int("n", g), f.read_attribute_double("phi_init", g),
               f.read_attribute_double("log10_rate", g)};
      if (f.has_attribute("chain_phi_init", g))
        e.chain_phi_init = f.read_attribute_double("chain_phi_init", g);
      e.constant_phi = read_average(f, g + "/constant_phi", "packing_fraction");
      if (f.has_dataset(g + "/constant_z"))
        e.constant_z = read_average(f, g + "/constant_z", z_grid_name(f, g + "/constant_z"));
      if (f.has_dataset(g + "/coverage")) e.coverage = read_coverage(f, g + "/coverage");
      if (f.has_dataset(g + "/jamming")) {
        // The runs' jamming points carry over as they were stored.
        const std::string jg = g + "/jamming";
        const std::vector<std::int64_t> ids = read_sample_ids(f, jg);
        e.jamming = jamming_stats(
            f.read_dataset(jg + "/packing_fraction_samples", h5::exactly(ids.size())), ids);
      }
      s.ensembles.push_back(std::move(e));
    }
  }
  if (s.ensembles.empty()) throw std::runtime_error(path + ": no ensembles");
  if (o.fit) fit_campaign(s, o);
  return s;
}

}  // namespace jam::stats
