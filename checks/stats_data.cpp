#include "checks/stats_data.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "checks/margin.hpp"
#include "sim/io/hdf5_file.hpp"
#include "stats/sample_ids.hpp"
#include "stats/stats_inputs.hpp"
#include "stats/stats_schema.hpp"

namespace jam::checks {
namespace {

/// A table of `rows` samples by `m` grid points, stored row by row: its length is checked
/// before it is read, so that every row is whole.
std::vector<std::vector<double>> table(const h5::File& f, const std::string& name, std::size_t rows,
                                       std::size_t m) {
  const auto flat = f.read_dataset(name, h5::exactly(rows * m));
  std::vector<std::vector<double>> out;
  for (std::size_t s = 0; m > 0 && s < rows; ++s) {
    out.emplace_back(flat.begin() + static_cast<long>(s * m),
                     flat.begin() + static_cast<long>((s + 1) * m));
  }
  return out;
}

/// The rows of a table whose row count is its own (constant Z keeps its own sample list).
int read_dim(const h5::File& f) {
  const std::int64_t dim = f.read_attribute_int("dim");
  if (dim != 2 && dim != 3) {
    throw std::runtime_error(
        fmt::format("{}: attribute 'dim' = {}, expected 2 or 3", f.path(), dim));
  }
  return static_cast<int>(dim);
}

/// The constant-Z table of an ensemble group g, when it has one.
void read_constant_z(const h5::File& f, const std::string& g, EnsembleTables& e) {
  if (!f.has_dataset(g + "/constant_z")) return;
  const std::string z = g + "/constant_z";
  const auto groups = f.list_group(z);
  const std::string grid_name =
      std::find(groups.begin(), groups.end(), "contacts_per_particle") != groups.end()
          ? "contacts_per_particle"
          : "contacts_per_particle_no_rattlers";
  e.z_grid = f.read_dataset(z + "/" + grid_name);
  // The checks take a run's rows of both tables as one sample (e.sample_ids, constant phi's):
  // a table of other samples, or of the same in another order, would pair the wrong runs.
  if (stats::read_sample_ids(f, z) != e.sample_ids) {
    throw std::runtime_error(fmt::format(
        "{}: dataset '{}/sample_ids' does not list the samples of '{}/constant_phi/sample_ids' "
        "in their order",
        f.path(), z, g));
  }
  e.pressure_at_z = table(f, z + "/pressure_samples", e.sample_ids.size(), e.z_grid.size());
  if (f.has_dataset(z + "/packing_fraction_mean"))
    e.phi_at_z = f.read_dataset(z + "/packing_fraction_mean", h5::exactly(e.z_grid.size()));
}

/// The mean over the finite values of each column (NaN where there is none).
std::vector<double> column_means(const std::vector<std::vector<double>>& rows, std::size_t m) {
  std::vector<double> sum(m, 0.0), count(m, 0.0);
  for (const auto& row : rows)
    for (std::size_t k = 0; k < m; ++k)
      if (std::isfinite(row[k])) sum[k] += row[k], count[k] += 1;
  for (std::size_t k = 0; k < m; ++k) sum[k] = count[k] > 0 ? sum[k] / count[k] : NAN;
  return sum;
}

/// ensembles/<name>/coverage/ of stats.h5 (stats/run_coverage.hpp) into e.coverage; its rows
/// must be e's samples in e's order, as constant Z's.
void read_coverage(const h5::File& f, const std::string& c, EnsembleTables& e) {
  const std::size_t rows = e.sample_ids.size();
  auto same_samples = [&](const std::string& group) {
    if (stats::read_sample_ids(f, group) != e.sample_ids) {
      throw std::runtime_error(fmt::format(
          "{}: dataset '{}/sample_ids' does not list the samples of the ensemble's constant_phi "
          "in their order",
          f.path(), group));
    }
  };
  same_samples(c);
  e.coverage.output_step = f.read_dataset(c + "/packing_fraction_step", h5::exactly(rows));
  if (f.has_dataset(c + "/constant_phi")) {
    const std::string g = c + "/constant_phi";
    same_samples(g);
    e.coverage.phi_grid = f.read_dataset(g + "/packing_fraction");
    e.coverage.pressure_at_phi =
        table(f, g + "/pressure_samples", rows, e.coverage.phi_grid.size());
  }
  if (f.has_dataset(c + "/constant_z")) {
    const std::string g = c + "/constant_z";
    same_samples(g);
    const auto names = f.list_group(g);
    e.coverage.z_grid = f.read_dataset(
        g + "/" +
        (std::find(names.begin(), names.end(), "contacts_per_particle") != names.end()
             ? "contacts_per_particle"
             : "contacts_per_particle_no_rattlers"));
    const std::size_t m = e.coverage.z_grid.size();
    e.coverage.pressure_at_z = table(f, g + "/pressure_samples", rows, m);
    e.coverage.phi_at_z = column_means(table(f, g + "/packing_fraction_samples", rows, m), m);
  }
}

EnsembleTables read_ensemble(const h5::File& f, const std::string& name) {
  const std::string g = "ensembles/" + name;
  const std::string phi = g + "/constant_phi";
  EnsembleTables e;
  e.name = name;
  e.n = f.read_attribute_int("n", g);
  e.phi_init = f.read_attribute_double("phi_init", g);
  e.log10_rate = f.read_attribute_double("log10_rate", g);
  if (f.has_attribute("chain_phi_init", g))
    e.chain_phi_init = f.read_attribute_double("chain_phi_init", g);
  e.phi_grid = f.read_dataset(phi + "/packing_fraction");
  e.sample_ids = stats::read_sample_ids(f, phi);
  const std::size_t rows = e.sample_ids.size(), m = e.phi_grid.size();
  e.pressure_at_phi = table(f, phi + "/pressure_samples", rows, m);
  read_constant_z(f, g, e);
  const std::string z_name = phi + "/contacts_per_particle_samples";
  if (f.has_dataset(z_name)) e.z_samples_at_phi = table(f, z_name, rows, m);
  const std::string z_nr_name = phi + "/contacts_per_particle_no_rattlers_samples";
  if (f.has_dataset(z_nr_name)) e.z_nr_samples_at_phi = table(f, z_nr_name, rows, m);
  find_compressed_range(e, e.z_samples_at_phi);
  if (!e.z_samples_at_phi.empty()) e.z_at_phi = column_means(e.z_samples_at_phi, m);
  if (f.has_dataset(g + "/jamming")) {
    e.jamming_sample_ids = stats::read_sample_ids(f, g + "/jamming");
    e.jamming_points = f.read_dataset(g + "/jamming/packing_fraction_samples",
                                      h5::exactly(e.jamming_sample_ids.size()));
  }
  if (f.has_dataset(g + "/coverage")) read_coverage(f, g + "/coverage", e);
  return e;
}

}  // namespace

void find_compressed_range(EnsembleTables& e, const std::vector<std::vector<double>>& z_at_phi) {
  const std::size_t k = e.chain_phi_init > 0 ? first_chained_compression_point(e.pressure_at_phi)
                                             : first_compression_point(e.pressure_at_phi);
  const bool found = k < e.phi_grid.size();
  e.compressed_from_phi = found ? e.phi_grid[k] : HUGE_VAL;
  e.compressed_from_z = found ? 0.0 : HUGE_VAL;
  if (found && !z_at_phi.empty()) {
    double mean = 0.0;
    for (const auto& row : z_at_phi) mean += row[k] / static_cast<double>(z_at_phi.size());
    e.compressed_from_z = mean;
  }
}

StatsData read_stats(const std::string& directory) {
  const std::string path = (std::filesystem::path(directory) / "stats.h5").string();
  if (!std::filesystem::exists(path)) {
    throw std::runtime_error(
        fmt::format("{}: no stats.h5; run `jam stats {}` first", directory, directory));
  }
  const h5::File f = h5::File::open_read(path);
  stats::check_stats_checksum(f, directory);  // a table changed by hand is not judged
  stats::check_stats_schema(f);               // reference/schema/stats.toml, as jamio checks it
  StatsData d;
  d.directory = directory;
  d.campaign = f.read_attribute_string("campaign");
  d.dim = read_dim(f);
  d.pooled = f.read_attribute_int("pooled_sizes") != 0;
  if (f.has_dataset("fit/representative")) {
    d.fit_window_min = f.read_attribute_double("phi_min", "fit/representative");
    // Older stats.h5 files name only the window's lower edge: then it is open above.
    if (f.has_attribute("phi_max", "fit/representative"))
      d.fit_window_max = f.read_attribute_double("phi_max", "fit/representative");
    d.fit_phi_j = f.read_attribute_double("phi_j", "fit/representative");
  }
  if (f.has_dataset("fit_z/representative") && f.has_attribute("phi_max", "fit_z/representative")) {
    d.fit_z_window_min = f.read_attribute_double("phi_min", "fit_z/representative");
    d.fit_z_window_max = f.read_attribute_double("phi_max", "fit_z/representative");
  }
  for (const auto& name : f.list_group("ensembles")) d.ensembles.push_back(read_ensemble(f, name));
  if (f.has_dataset("fit/families")) {
    for (const auto& name : f.list_group("fit/families")) {
      const std::string g = "fit/families/" + name;
      FamilyParameters p;
      p.n = f.read_attribute_int("n", g);
      p.phi_init = f.read_attribute_double("family_phi_init", g);
      if (f.has_attribute("failure", g)) {
        p.failure = f.read_attribute_string("failure", g);
      } else {
        for (auto [key, value] : {std::pair{"phi_j", &p.phi_j},
                                  {"phi_j_error", &p.phi_j_err},
                                  {"beta", &p.beta},
                                  {"beta_error", &p.beta_err},
                                  {"y", &p.y},
                                  {"y_error", &p.y_err}})
          *value = f.read_attribute_double(key, g);
        p.samples = f.read_attribute_int("samples", g);
        if (f.has_attribute("quality", g)) p.quality = f.read_attribute_string("quality", g);
        if (f.has_attribute("quality_reason", g))
          p.quality_reason = f.read_attribute_string("quality_reason", g);
      }
      d.families.push_back(std::move(p));
    }
  }
  return d;
}

Aligned align(const std::vector<double>& ga, const std::vector<std::vector<double>>& a,
              const std::vector<double>& gb, const std::vector<std::vector<double>>& b,
              double grid_min, double grid_max) {
  Aligned r;
  std::vector<std::size_t> ia, ib;
  std::size_t j = 0;
  for (std::size_t i = 0; i < ga.size(); ++i) {
    while (j < gb.size() && gb[j] < ga[i] - 1e-9) ++j;
    if (j < gb.size() && std::abs(gb[j] - ga[i]) < 1e-9 && ga[i] >= grid_min - 1e-12 &&
        ga[i] <= grid_max + 1e-12) {
      ia.push_back(i);
      ib.push_back(j);
      r.grid.push_back(ga[i]);
    }
  }
  for (const auto& row : a) {
    std::vector<double> v;
    for (auto i : ia) v.push_back(row[i]);
    r.a.push_back(std::move(v));
  }
  for (const auto& row : b) {
    std::vector<double> v;
    for (auto i : ib) v.push_back(row[i]);
    r.b.push_back(std::move(v));
  }
  return r;
}

std::string case_label(const EnsembleTables& e) {
  return fmt::format("n{} phi_init {:g} rate 1e{:g}", e.n, e.phi_init, e.log10_rate);
}

}  // namespace jam::checks
