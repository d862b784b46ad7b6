// DIR/stats.h5 and the printed summary of `jam stats` (schema in reference/schema.md).
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/version.hpp"
#include "stats/campaign_stats.hpp"

namespace jam::stats {
namespace {

std::string ensemble_name(const EnsembleKey& k) {
  return fmt::format("{}_phi{:.4f}_r{:+.2f}", k.n ? fmt::format("n{}", k.n) : std::string("pooled"),
                     k.phi_init, k.log10_rate);
}

std::vector<double> flatten(const std::vector<std::vector<double>>& table) {
  std::vector<double> v;
  for (const auto& row : table) v.insert(v.end(), row.begin(), row.end());
  return v;
}

void write_average(h5::File& f, const std::string& group, const GridAverage& a) {
  f.create_group(group);
  f.write_dataset(group + "/" + a.grid_name, a.grid);
  std::vector<std::uint32_t> ids(a.sample_ids.begin(), a.sample_ids.end());
  f.write_dataset(group + "/sample_ids", ids);
  for (std::size_t o = 0; o < a.names.size(); ++o) {
    std::vector<double> mean, error, relative;
    for (const auto& m : a.means[o]) {
      mean.push_back(m.mean);
      error.push_back(m.error);
      relative.push_back(m.error / std::abs(m.mean));
    }
    const std::string base = group + "/" + a.names[o];
    f.write_dataset(base + "_mean", mean);
    f.write_dataset(base + "_error", error);
    f.write_dataset(base + "_relative_error", relative);
    f.write_dataset(base + "_samples", flatten(a.tables[o]), {a.tables[o].size(), a.grid.size()});
  }
  f.write_attribute("error_method", std::string(SampleMean::kMethod), group);
}

void write_fit(h5::File& f, const std::string& group, const ScalingFitResult& r, const ScanRow& row,
               int order) {
  f.create_group(group);
  auto attr = [&](const char* name, double v) { f.write_attribute(name, v, group); };
  attr("phi_j", r.phi_j);
  attr("phi_j_error", r.phi_j_err);
  attr("q", r.q);
  attr("q_error", r.q_err);
  attr("inv_znu", r.inv_znu);
  attr("inv_znu_error", r.inv_znu_err);
  attr("beta", r.beta);
  attr("beta_error", r.beta_err);
  attr("y", r.y);
  attr("y_error", r.y_err);
  attr("chi2_diag_per_dof", r.chi2_diag_per_dof);
  attr("chi2_cov_per_dof", r.chi2_cov_per_dof);
  attr("covariance_shrinkage", r.shrinkage);
  attr("condition_number", r.condition_number);
  attr("phi_min", row.phi_min);
  attr("phi_max", row.phi_max);
  attr("rate_max", row.rate_max);
  f.write_attribute("points", static_cast<std::int64_t>(r.points), group);
  f.write_attribute("samples", static_cast<std::int64_t>(r.samples), group);
  f.write_attribute("order", std::int64_t{order}, group);
  f.write_attribute("fixed", r.fixed.empty() ? std::string("none") : r.fixed, group);
  f.write_attribute("error_method", r.error_method, group);
  f.write_dataset(group + "/coefficients", r.coefficients);
  std::vector<double> rate, phi, x, scaled, scaled_err, in_fit;
  for (const auto& c : r.collapse) {
    rate.push_back(c.rate);
    phi.push_back(c.phi);
    x.push_back(c.x);
    scaled.push_back(c.scaled_pressure);
    scaled_err.push_back(c.scaled_error);
    in_fit.push_back(c.in_fit ? 1.0 : 0.0);
  }
  f.write_dataset(group + "/collapse/compression_rate", rate);
  f.write_dataset(group + "/collapse/packing_fraction", phi);
  f.write_dataset(group + "/collapse/x", x);
  f.write_dataset(group + "/collapse/scaled_pressure", scaled);
  f.write_dataset(group + "/collapse/scaled_pressure_error", scaled_err);
  f.write_dataset(group + "/collapse/in_fit", in_fit);
}

}  // namespace

void write_stats_file(const std::string& path, const CampaignStats& s, const StatsOptions& o) {
  const std::string temporary = AtomicFile::temporary_name(path);
  try {
    h5::File f = h5::File::create(temporary);
    f.write_attribute("campaign", s.data.name);
    f.write_attribute("dim", std::int64_t{s.data.dim});
    f.write_attribute("version", std::string(kVersion));
    f.write_attribute("runs", static_cast<std::int64_t>(s.data.runs.size()));
    f.write_attribute("runs_skipped", static_cast<std::int64_t>(s.data.skipped.size()));
    f.write_attribute("pooled_sizes", std::int64_t{o.pool_sizes});
    f.write_attribute("z_step", o.z_step);
    f.write_attribute("constant_z_without_rattlers", std::int64_t{o.no_rattlers});
    f.write_attribute("wall_time", s.wall_time);
    // The published values, for reports to compare with (one source: paper_values.hpp).
    const PaperValues paper = paper_values(s.data.dim);
    f.create_group("paper");
    for (const auto& [name, value] :
         {std::pair{"phi_j", paper.phi_j}, std::pair{"phi_j_error", paper.phi_j_error},
          std::pair{"beta", paper.beta}, std::pair{"beta_error", paper.beta_error},
          std::pair{"y", paper.y}, std::pair{"y_error", paper.y_error}}) {
      f.write_attribute(name, value, "paper");
    }
    for (const auto& e : s.ensembles) {
      const std::string g = "ensembles/" + ensemble_name(e.key);
      f.create_group(g);
      f.write_attribute("n", e.key.n, g);
      f.write_attribute("phi_init", e.key.phi_init, g);
      f.write_attribute("log10_rate", e.key.log10_rate, g);
      f.write_attribute("compression_rate", std::pow(10.0, e.key.log10_rate), g);
      f.write_attribute("samples", static_cast<std::int64_t>(e.constant_phi.sample_ids.size()), g);
      write_average(f, g + "/constant_phi", e.constant_phi);
      if (e.constant_z) write_average(f, g + "/constant_z", *e.constant_z);
      if (e.jamming) {
        const std::string jg = g + "/jamming";
        f.create_group(jg);
        f.write_dataset(jg + "/packing_fraction_samples", e.jamming->samples);
        f.write_dataset(
            jg + "/sample_ids",
            std::vector<std::uint32_t>(e.jamming->sample_ids.begin(), e.jamming->sample_ids.end()));
        f.write_attribute("mean", e.jamming->mean.mean, jg);
        f.write_attribute("error", e.jamming->mean.error, jg);
        f.write_attribute("spread", e.jamming->spread, jg);
        f.write_attribute("found", static_cast<std::int64_t>(e.jamming->mean.samples), jg);
      }
    }
    if (!s.scan.empty()) {
      f.create_group("fit");
      f.write_attribute("phi_init", s.fit_phi_init, "fit");
      f.write_attribute("n", s.fit_size, "fit");
      if (s.fit) write_fit(f, "fit/representative", *s.fit, s.fit_row, o.order);
      if (!s.fit_failure.empty()) f.write_attribute("failure", s.fit_failure, "fit");
      std::vector<double> cols[11];
      std::string failures;
      for (const auto& row : s.scan) {
        const double nan = std::nan("");
        const auto& r = row.result;
        const double values[11] = {row.rate_max,
                                   row.phi_min,
                                   row.phi_max,
                                   r ? r->phi_j : nan,
                                   r ? r->phi_j_err : nan,
                                   r ? r->beta : nan,
                                   r ? r->beta_err : nan,
                                   r ? r->y : nan,
                                   r ? r->y_err : nan,
                                   r ? r->chi2_diag_per_dof : nan,
                                   r ? r->chi2_cov_per_dof : nan};
        for (int k = 0; k < 11; ++k) cols[k].push_back(values[k]);
        if (!r)
          failures += fmt::format("rate_max {:g} phi [{:g}, {:g}]: {}\n", row.rate_max, row.phi_min,
                                  row.phi_max, row.failure);
      }
      const char* names[11] = {"rate_max",        "phi_min",
                               "phi_max",         "phi_j",
                               "phi_j_error",     "beta",
                               "beta_error",      "y",
                               "y_error",         "chi2_diag_per_dof",
                               "chi2_cov_per_dof"};
      for (int k = 0; k < 11; ++k) f.write_dataset(std::string("fit/scan/") + names[k], cols[k]);
      f.write_attribute("failures", failures.empty() ? std::string("none") : failures, "fit/scan");
    }
    f.close();
    AtomicFile::publish(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

std::string format_stats_summary(const CampaignStats& s) {
  std::ostringstream out;
  out << fmt::format("campaign {}: {} runs averaged, {} skipped (not finished)\n", s.data.name,
                     s.data.runs.size(), s.data.skipped.size());
  const double probe = s.data.dim == 2 ? 0.84 : 0.64;
  out << fmt::format("\n{:>8} {:>8} {:>9} {:>7} {:>13} {:>9} {:>9} {:>9}\n", "N", "phi_init",
                     "rate", "samples", fmt::format("p({:.2f})", probe), "dp/p", "Z", "dZ/Z");
  for (const auto& e : s.ensembles) {
    const auto& a = e.constant_phi;
    std::size_t k = 0;
    while (k + 1 < a.grid.size() && a.grid[k] < probe - 1e-9) ++k;
    const auto& p = a.mean("pressure")[k];
    const auto& z = a.mean("contacts_per_particle")[k];
    out << fmt::format(
        "{:>8} {:>8.4f} {:>9.2e} {:>7} {:>13.4e} {:>8.1f}% {:>9.4f} {:>8.2f}%{}\n",
        e.key.n ? std::to_string(e.key.n) : "pooled", e.key.phi_init,
        std::pow(10.0, e.key.log10_rate), a.sample_ids.size(), p.mean, 100 * p.error / p.mean,
        z.mean, 100 * z.error / z.mean,
        std::abs(a.grid[k] - probe) > 1e-9 ? fmt::format("  (at phi {:.4f})", a.grid[k]) : "");
  }
  bool any_jamming = false;
  for (const auto& e : s.ensembles) any_jamming = any_jamming || e.jamming.has_value();
  if (any_jamming) {
    out << fmt::format("\n{:>8} {:>8} {:>9} {:>18} {:>10} {:>6}\n", "N", "phi_init", "rate",
                       "<phi_Ji>", "spread", "found");
    for (const auto& e : s.ensembles) {
      if (!e.jamming) continue;
      out << fmt::format("{:>8} {:>8.4f} {:>9.2e} {:>9.5f}({:>7.5f}) {:>10.5f} {:>3}/{}\n",
                         e.key.n ? std::to_string(e.key.n) : "pooled", e.key.phi_init,
                         std::pow(10.0, e.key.log10_rate), e.jamming->mean.mean,
                         e.jamming->mean.error, e.jamming->spread, e.jamming->mean.samples,
                         e.jamming->samples.size());
    }
  }
  if (!s.scan.empty()) {
    out << fmt::format(
        "\nscaling fit (phi_init {:g}, N {}): phi_J, beta = (1-q) z nu, y = q z nu; "
        "errors: jackknife over samples\n",
        s.fit_phi_init, s.fit_size ? std::to_string(s.fit_size) : "pooled");
    out << fmt::format("{:>9} {:>15} {:>17} {:>13} {:>13} {:>9} {:>9} {:>8} {:>6}\n", "rate_max",
                       "phi window", "phi_J", "beta", "y", "chi2/nf", "(cov)", "cond", "points");
    for (const auto& row : s.scan) {
      const std::string window = fmt::format("{:.4f}-{:.4f}", row.phi_min, row.phi_max);
      if (!row.result) {
        out << fmt::format("{:>9.2e} {:>15}   fit failed: {}\n", row.rate_max, window, row.failure);
        continue;
      }
      const auto& r = *row.result;
      out << fmt::format(
          "{:>9.2e} {:>15} {:>8.5f}({:>7.5f}) {:>6.3f}({:>5.3f}) {:>6.3f}({:>5.3f}) {:>9.3f} "
          "{:>9.3f} {:>8.1e} {:>6}\n",
          row.rate_max, window, r.phi_j, r.phi_j_err, r.beta, r.beta_err, r.y, r.y_err,
          r.chi2_diag_per_dof, r.chi2_cov_per_dof, r.condition_number, r.points);
    }
    if (s.fit) {
      out << fmt::format("fixed: {}\n", s.fit->fixed.empty() ? "nothing" : s.fit->fixed);
    }
  }
  return out.str();
}

}  // namespace jam::stats
