// DIR/stats.h5 and the printed summary of `jam stats` (schema in reference/schema.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "sim/io/atomic_file.hpp"
#include "sim/io/content_checksum.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/output_path.hpp"
#include "sim/io/run_file.hpp"
#include "sim/model/paper_values.hpp"
#include "sim/run/stop_signal.hpp"
#include "sim/version.hpp"
#include "stats/campaign_stats.hpp"
#include "stats/papers_protocol.hpp"
#include "stats/scan_failures.hpp"
#include "stats/stats_schema.hpp"

namespace jam::stats {
namespace {

std::string ensemble_name(const EnsembleKey& k) {
  return fmt::format("{}_phi{:.4f}_r{:+.2f}", k.n ? fmt::format("n{}", k.n) : std::string("pooled"),
                     k.phi_init, k.log10_rate);
}

// Units of the datasets (attribute `units`, as the run files carry theirs, sim/io/run_file.cpp):
// every number is in the paper's units (d_s = k_e = t0 = 1, docs/model.md), so the attribute
// says what a value is a multiple of, for readers that put units on their tables.
constexpr const char* kDimensionless = "1";
constexpr const char* kPressureUnit = "k_e/d_s^D";
constexpr const char* kRateUnit = "1/t0";
// The collapse's axes: x = (phi - phi_J) / rate^(1/(z nu)), p / rate^q (q, 1/(z nu) the fit's).
constexpr const char* kScalingVariableUnit = "t0^(1/(z nu))";
constexpr const char* kScaledPressureUnit = "k_e/d_s^D t0^q";

/// Pressure is the one averaged observable with a unit; packing fraction and Z are numbers.
const char* unit_of(const std::string& observable) {
  return observable == "pressure" ? kPressureUnit : kDimensionless;
}

void write_dataset(h5::File& f, const std::string& path, const std::vector<double>& values,
                   const char* unit, const std::vector<hsize_t>& shape = {}) {
  f.write_dataset(path, values, shape);
  f.write_attribute("units", std::string(unit), path);
}

std::vector<double> flatten(const std::vector<std::vector<double>>& table) {
  std::vector<double> v;
  for (const auto& row : table) v.insert(v.end(), row.begin(), row.end());
  return v;
}

void write_average(h5::File& f, const std::string& group, const GridAverage& a) {
  f.create_group(group);
  write_dataset(f, group + "/" + a.grid_name, a.grid, unit_of(a.grid_name));
  // float64: pooled sizes number their samples n * 10^7 + sample (run_curves.hpp), beyond 32
  // bits; every such integer is exact in a double.
  std::vector<double> ids(a.sample_ids.begin(), a.sample_ids.end());
  write_dataset(f, group + "/sample_ids", ids, kDimensionless);
  for (std::size_t o = 0; o < a.names.size(); ++o) {
    std::vector<double> mean, error, relative;
    for (const auto& m : a.means[o]) {
      mean.push_back(m.mean);
      error.push_back(m.error);
      relative.push_back(m.error / std::abs(m.mean));
    }
    const std::string base = group + "/" + a.names[o];
    const char* unit = unit_of(a.names[o]);
    write_dataset(f, base + "_mean", mean, unit);
    write_dataset(f, base + "_error", error, unit);
    write_dataset(f, base + "_relative_error", relative, kDimensionless);
    write_dataset(f, base + "_samples", flatten(a.tables[o]), unit,
                  {a.tables[o].size(), a.grid.size()});
  }
  f.write_attribute("error_method", std::string(SampleMean::kMethod), group);
}

/// ensembles/<name>/coverage/ (run_coverage.hpp): each run's last output packing and output
/// spacing, and the tables over the grid any run reaches when it is longer than the common one.
void write_coverage(h5::File& f, const std::string& group, const RunCoverage& c) {
  f.create_group(group);
  write_dataset(f, group + "/sample_ids",
                std::vector<double>(c.sample_ids.begin(), c.sample_ids.end()), kDimensionless);
  write_dataset(f, group + "/packing_fraction_last", c.phi_last, kDimensionless);
  write_dataset(f, group + "/packing_fraction_step", c.output_step, kDimensionless);
  if (c.constant_phi) write_average(f, group + "/constant_phi", *c.constant_phi);
  if (c.constant_z) write_average(f, group + "/constant_z", *c.constant_z);
}

void write_fit(h5::File& f, const std::string& group, const ScalingFitResult& r, const ScanRow& row,
               int order);

/// fit/families/n<N>_phi<phi_init>: each (N, phi_init) fitted as the representative.
void write_families(h5::File& f, const CampaignStats& s, int order) {
  if (s.families.empty() || !s.fit.representative()) return;
  const ScanRow& row = s.fit.rows[*s.fit.chosen];
  f.create_group("fit/families");
  for (const auto& family : s.families) {
    const std::string g = fmt::format("fit/families/n{}_phi{:.4f}", family.n, family.phi_init);
    if (family.result) {
      write_fit(f, g, *family.result, row, order);
    } else {
      f.create_group(g);
      f.write_attribute("failure", family.failure, g);
    }
    f.write_attribute("n", family.n, g);
    f.write_attribute("family_phi_init", family.phi_init, g);
  }
}

void write_fit(h5::File& f, const std::string& group, const ScalingFitResult& r, const ScanRow& row,
               int order) {
  f.create_group(group);
  auto attr = [&](const char* name, double v) { f.write_attribute(name, v, group); };
  // Bias-corrected (jackknife) values with their errors, and the plain fit beside them.
  const double values[][3] = {{r.phi_j, r.phi_j_err, r.phi_j_plain},
                              {r.rate_exponent, r.rate_exponent_err, r.rate_exponent_plain},
                              {r.inv_znu, r.inv_znu_err, r.inv_znu_plain},
                              {r.beta, r.beta_err, r.beta_plain},
                              {r.y, r.y_err, r.y_plain}};
  const char* names[] = {"phi_j", "q", "inv_znu", "beta", "y"};
  for (int k = 0; k < 5; ++k) {
    attr(names[k], values[k][0]);
    f.write_attribute(std::string(names[k]) + "_error", values[k][1], group);
    f.write_attribute(std::string(names[k]) + "_plain", values[k][2], group);
  }
  attr("chi2_diag_per_dof", r.chi2_diag_per_dof);
  attr("chi2_cov_per_dof", r.chi2_cov_per_dof);
  attr("covariance_shrinkage", r.shrinkage);
  attr("condition_number", r.condition_number);
  attr("phi_min", r.phi_min);
  attr("phi_max", r.phi_max);
  attr("half_window", row.half_window);
  attr("rate_max", row.rate_max);
  f.write_attribute("points", static_cast<std::int64_t>(r.points), group);
  f.write_attribute("min_points_per_rate", static_cast<std::int64_t>(r.min_points_per_rate), group);
  f.write_attribute("iterations", std::int64_t{r.iterations}, group);
  f.write_attribute("start", r.start, group);
  f.write_attribute("quality", r.quality, group);
  f.write_attribute("quality_reason",
                    r.quality_reason.empty() ? std::string("-") : r.quality_reason, group);
  f.write_attribute("samples", static_cast<std::int64_t>(r.samples), group);
  f.write_attribute("order", std::int64_t{order}, group);
  f.write_attribute("fixed", r.fixed.empty() ? std::string("none") : r.fixed, group);
  f.write_attribute("error_method", r.error_method, group);
  // c_k of ln f(x), fitted to the numbers in the paper's units (ln p, ln rate): numbers.
  write_dataset(f, group + "/coefficients", r.coefficients, kDimensionless);
  std::vector<double> rate, phi, x, scaled, scaled_err, in_fit;
  for (const auto& c : r.collapse) {
    rate.push_back(c.rate);
    phi.push_back(c.phi);
    x.push_back(c.x);
    scaled.push_back(c.scaled_pressure);
    scaled_err.push_back(c.scaled_error);
    in_fit.push_back(c.in_fit ? 1.0 : 0.0);
  }
  write_dataset(f, group + "/collapse/compression_rate", rate, kRateUnit);
  write_dataset(f, group + "/collapse/packing_fraction", phi, kDimensionless);
  write_dataset(f, group + "/collapse/x", x, kScalingVariableUnit);
  write_dataset(f, group + "/collapse/scaled_pressure", scaled, kScaledPressureUnit);
  write_dataset(f, group + "/collapse/scaled_pressure_error", scaled_err, kScaledPressureUnit);
  write_dataset(f, group + "/collapse/in_fit", in_fit, kDimensionless);
}

void write_scan(h5::File& f, const std::string& group, const FitScan& scan) {
  const char* names[] = {"rate_max",
                         "half_window",
                         "phi_min",
                         "phi_max",
                         "phi_j",
                         "phi_j_error",
                         "q",
                         "q_error",
                         "inv_znu",
                         "inv_znu_error",
                         "beta",
                         "beta_error",
                         "y",
                         "y_error",
                         "chi2_diag_per_dof",
                         "chi2_cov_per_dof",
                         "iterations",
                         "quality_ok",
                         "chosen",
                         "papers_protocol"};
  constexpr std::size_t columns = std::size(names);
  std::vector<double> cols[columns];
  std::string failures;
  for (std::size_t k = 0; k < scan.rows.size(); ++k) {
    const auto& row = scan.rows[k];
    const double nan = std::nan("");
    const auto& r = row.result;
    const double values[columns] = {row.rate_max,
                                    row.half_window,
                                    r ? r->phi_min : nan,
                                    r ? r->phi_max : nan,
                                    r ? r->phi_j : nan,
                                    r ? r->phi_j_err : nan,
                                    r ? r->rate_exponent : nan,
                                    r ? r->rate_exponent_err : nan,
                                    r ? r->inv_znu : nan,
                                    r ? r->inv_znu_err : nan,
                                    r ? r->beta : nan,
                                    r ? r->beta_err : nan,
                                    r ? r->y : nan,
                                    r ? r->y_err : nan,
                                    r ? r->chi2_diag_per_dof : nan,
                                    r ? r->chi2_cov_per_dof : nan,
                                    r ? static_cast<double>(r->iterations) : nan,
                                    r ? (r->quality == "ok" ? 1.0 : 0.0) : nan,
                                    scan.chosen == k ? 1.0 : 0.0,
                                    scan.papers_protocol == k ? 1.0 : 0.0};
    for (std::size_t c = 0; c < columns; ++c) cols[c].push_back(values[c]);
    if (!r) {
      failures += fmt::format("rate_max {:g} window +-{:g}: {}\n", row.rate_max, row.half_window,
                              row.failure);
    }
  }
  // rate_max is a rate; every other column (packings, exponents, chi^2, counts, flags) a number.
  for (std::size_t c = 0; c < columns; ++c) {
    const bool rate = std::string(names[c]) == "rate_max";
    write_dataset(f, group + "/" + names[c], cols[c], rate ? kRateUnit : kDimensionless);
  }
  f.write_attribute("failures", failures.empty() ? std::string("none") : failures, group);
}

}  // namespace

void write_stats_file(const std::string& given, const CampaignStats& s, const StatsOptions& o) {
  const std::string path = output_file_target(given);
  const std::string temporary = AtomicFile::temporary_name(path);
  try {
    h5::File f = h5::File::create(temporary);
    // The layout's version (reference/schema/stats.toml): a reader of another refuses the file.
    f.write_attribute("schema_version", std::int64_t{current_stats_schema_version()});
    f.write_attribute("campaign", s.data.name);
    f.write_attribute("dim", std::int64_t{s.data.dim});
    f.write_attribute("version", std::string(kVersion));
    f.write_attribute("runs", s.runs_averaged);
    f.write_attribute("runs_skipped", s.runs_skipped);
    if (!s.refit_from.empty()) f.write_attribute("refit_from", s.refit_from);
    if (!s.inputs_checksum.empty()) f.write_attribute("inputs_checksum", s.inputs_checksum);
    f.write_attribute("pooled_sizes", std::int64_t{o.pool_sizes});
    f.write_attribute("z_step", o.z_step);
    f.write_attribute("constant_z_without_rattlers", std::int64_t{o.no_rattlers});
    f.write_attribute("wall_time", s.wall_time);
    // The verdicts declared to the fit (fit_verdicts.hpp): which files, the digest `jam
    // pipeline` compares to redo the fit when they change, and their bytes' checksum.
    // The verdicts the fit consulted (fit_verdicts.hpp): which files ("none"), their digest,
    // which `jam pipeline` compares to redo the fit when they change, the fit they were
    // consulted for, and the checksum of the files' bytes.
    const FitVerdicts& used = s.fit_verdicts;
    f.write_attribute("fit_verdicts", used.files.empty() ? std::string("none") : used.files);
    f.write_attribute("fit_verdicts_checksum", used.checksum());
    if (s.fit_selection.fitted) {
      f.write_attribute("fit_verdicts_n", s.fit_selection.n);
      f.write_attribute("fit_verdicts_phi_init", s.fit_selection.phi_init);
    }
    if (!used.files_checksum.empty())
      f.write_attribute("fit_verdicts_files_checksum", used.files_checksum);
    f.write_attribute("units", std::string(kRunFileUnits));
    // The output grid's spacing as the campaign file gives it, so that readers can put the
    // constant-phi grid on exact values k * phi_step (NaN: a refit of a file without it).
    if (std::isfinite(s.data.phi_step)) f.write_attribute("phi_step", s.data.phi_step);
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
      f.write_attribute("chain_phi_init", e.chain_phi_init, g);
      f.write_attribute("samples", static_cast<std::int64_t>(e.constant_phi.sample_ids.size()), g);
      write_average(f, g + "/constant_phi", e.constant_phi);
      if (e.constant_z) write_average(f, g + "/constant_z", *e.constant_z);
      if (e.jamming) {
        const std::string jg = g + "/jamming";
        f.create_group(jg);
        write_dataset(f, jg + "/packing_fraction_samples", e.jamming->samples, kDimensionless);
        write_dataset(
            f, jg + "/sample_ids",
            std::vector<double>(e.jamming->sample_ids.begin(), e.jamming->sample_ids.end()),
            kDimensionless);
        f.write_attribute("mean", e.jamming->mean.mean, jg);
        f.write_attribute("error", e.jamming->mean.error, jg);
        f.write_attribute("spread", e.jamming->spread, jg);
        f.write_attribute("found", static_cast<std::int64_t>(e.jamming->mean.samples), jg);
      }
      if (e.coverage) write_coverage(f, g + "/coverage", *e.coverage);
    }
    for (const auto& [group, scan] :
         {std::pair{std::string("fit"), &s.fit}, std::pair{std::string("fit_z"), &s.fit_z}}) {
      if (scan->rows.empty()) continue;
      f.create_group(group);
      f.write_attribute("phi_init", s.fit_phi_init, group);
      f.write_attribute("n", s.fit_size, group);
      f.write_attribute("rates_note", s.clearance.note, group);
      if (const auto* r = scan->representative()) {
        write_fit(f, group + "/representative", *r, scan->rows[*scan->chosen], o.order);
        f.write_attribute("chosen_because", scan->reason, group + "/representative");
        // The scan's own spread (campaign_stats.hpp, FitScan::systematic).
        f.write_attribute("phi_j_systematic", scan->systematic.phi_j, group + "/representative");
        f.write_attribute("beta_systematic", scan->systematic.beta, group + "/representative");
        f.write_attribute("y_systematic", scan->systematic.y, group + "/representative");
        f.write_attribute("systematic_fits", static_cast<std::int64_t>(scan->systematic.fits),
                          group + "/representative");
        f.write_attribute("plateau", static_cast<std::int64_t>(scan->plateau),
                          group + "/representative");
      }
      if (!scan->failure.empty()) f.write_attribute("failure", scan->failure, group);
      write_scan(f, group + "/scan", *scan);
    }
    write_families(f, s, o.order);
    if (s.papers_protocol && f.has_dataset("fit")) {
      // The paper's protocol, labelled: never the representative (papers_protocol.hpp).
      const PapersProtocolFit& p = *s.papers_protocol;
      if (p.result) {
        write_fit(f, "fit/papers_protocol", *p.result, p.row, kPapersOrder);
      } else {
        f.create_group("fit/papers_protocol");
        f.write_attribute("failure", p.failure, "fit/papers_protocol");
      }
      f.write_attribute("how", p.how, "fit/papers_protocol");
    }
    // The checksum of everything above (inputs_checksum with it), verified by every reader:
    // a table changed by hand is refused, not judged (content_checksum.hpp).
    seal(f);
    f.close();
    // A stop asked for meanwhile (`jam pipeline`, `--until-decided`): nothing is published.
    throw_if_stop_requested("stats.h5");
    AtomicFile::publish(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

std::string format_stats_summary(const CampaignStats& s) {
  std::ostringstream out;
  out << fmt::format("campaign {}: {} runs averaged, {} skipped (not finished)\n", s.data.name,
                     s.runs_averaged, s.runs_skipped);
  const double probe = s.data.dim == 2 ? 0.84 : 0.64;
  out << fmt::format("\n{:>8} {:>8} {:>9} {:>7} {:>13} {:>9} {:>9} {:>9}\n", "N", "phi_init",
                     "rate", "samples", fmt::format("p({:.2f})", probe), "dp/p", "Z", "dZ/Z");
  for (const auto& e : s.ensembles) {
    const auto& a = e.constant_phi;
    std::size_t k = 0;
    while (k + 1 < a.grid.size() && a.grid[k] < probe - 1e-9) ++k;
    const auto& p = a.mean("pressure")[k];
    // Runs of other simulators may carry no Z: shown as nan.
    const bool has_z =
        std::find(a.names.begin(), a.names.end(), "contacts_per_particle") != a.names.end();
    const SampleMean z = has_z ? a.mean("contacts_per_particle")[k] : SampleMean{NAN, NAN, 0};
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
  // No fit attempted (fewer than 3 rates, campaign_stats.hpp): one line, once.
  if (s.fit.rows.empty() && !s.fit.failure.empty())
    out << fmt::format("\nscaling fit: {}\n", s.fit.failure);
  for (const auto& [title, scan] :
       {std::pair{"constant phi", &s.fit}, std::pair{"constant Z", &s.fit_z}}) {
    if (scan->rows.empty()) continue;
    const std::size_t failed = static_cast<std::size_t>(std::count_if(
        scan->rows.begin(), scan->rows.end(), [](const ScanRow& r) { return !r.result; }));
    // Every row failed: one line with each reason once (stats.h5 fit/scan keeps every row).
    if (failed == scan->rows.size()) {
      out << fmt::format(
          "\nscaling fit at {} (phi_init {:g}, N {}): none of the {} fits could be made ({})\n",
          title, s.fit_phi_init, s.fit_size ? std::to_string(s.fit_size) : "pooled", failed,
          scan_failure_words(*scan));
      continue;
    }
    out << fmt::format(
        "\nscaling fit at {} (phi_init {:g}, N {}): phi_J, beta = (1-q) z nu, y = q z nu; "
        "jackknife over samples, bias-corrected (plain fit in the representative line)\n",
        title, s.fit_phi_init, s.fit_size ? std::to_string(s.fit_size) : "pooled");
    out << fmt::format("{:>9} {:>15} {:>17} {:>13} {:>13} {:>9} {:>9} {:>8} {:>4} {:>5}\n",
                       "rate_max", "phi window", "phi_J", "beta", "y", "chi2/nf", "(cov)", "cond",
                       "it", "flag");
    for (std::size_t k = 0; k < scan->rows.size(); ++k) {
      const auto& row = scan->rows[k];
      if (!row.result) continue;  // folded into one line below the table
      const auto& r = *row.result;
      out << fmt::format(
          "{:>9.2e} {:>15} {:>8.5f}({:>7.5f}) {:>6.3f}({:>5.3f}) {:>6.3f}({:>5.3f}) {:>9.3f} "
          "{:>9.3f} {:>8.1e} {:>4} {:>5}{}{}\n",
          row.rate_max, fmt::format("{:.4f}-{:.4f}", r.phi_min, r.phi_max), r.phi_j, r.phi_j_err,
          r.beta, r.beta_err, r.y, r.y_err, r.chi2_diag_per_dof, r.chi2_cov_per_dof,
          r.condition_number, r.iterations, r.quality,
          scan->chosen == k ? "  <- representative" : "",
          scan->papers_protocol == k ? "  <- the paper's protocol" : "");
    }
    if (failed > 0)
      out << fmt::format("not fitted: {} of the {} rows ({})\n", failed, scan->rows.size(),
                         scan_failure_words(*scan));
    if (const auto* r = scan->representative()) {
      out << fmt::format(
          "representative: phi_J {:.5f}({:.5f}) [plain {:.5f}], q {:.4f} [{:.4f}], "
          "1/(z nu) {:.4f} [{:.4f}], beta {:.3f} [{:.3f}], y {:.3f} [{:.3f}]; "
          "fixed: {}; quality {}{}\n",
          r->phi_j, r->phi_j_err, r->phi_j_plain, r->rate_exponent, r->rate_exponent_plain,
          r->inv_znu, r->inv_znu_plain, r->beta, r->beta_plain, r->y, r->y_plain,
          r->fixed.empty() ? "nothing" : r->fixed, r->quality,
          r->quality_reason.empty() ? "" : " (" + r->quality_reason + ")");
      out << "  chosen: " << scan->reason << "\n";
      if (scan == &s.fit && s.papers_protocol) {
        const PapersProtocolFit& p = *s.papers_protocol;
        if (p.result)
          out << fmt::format(
              "  {}: phi_J {:.5f}({:.5f}), beta {:.3f}({:.3f}), y {:.3f}({:.3f}), chi2/nf {:.3g}, "
              "quality {}{}\n",
              p.how, p.result->phi_j, p.result->phi_j_err, p.result->beta, p.result->beta_err,
              p.result->y, p.result->y_err, p.result->chi2_diag_per_dof, p.result->quality,
              p.result->quality_reason.empty() ? "" : " (" + p.result->quality_reason + ")");
        else
          out << "  " << p.how << ": no fit: " << p.failure << "\n";
      }
      out << fmt::format(
          "  systematic (the largest distance of the scan's {} fits of quality ok from it: "
          "windows and rate_max): phi_J +-{:.5f}, beta +-{:.3f}, y +-{:.3f}\n",
          scan->systematic.fits, scan->systematic.phi_j, scan->systematic.beta, scan->systematic.y);
    } else {
      out << "no representative fit: " << scan->failure << "\n";
    }
  }
  return out.str();
}

}  // namespace jam::stats
