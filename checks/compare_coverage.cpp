#include "checks/compare_coverage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "checks/compare_check.hpp"
#include "checks/margin.hpp"

namespace jam::checks {
namespace {

/// The last grid value where a row has data (-inf when it has none).
double last_with_data(const std::vector<double>& grid, const std::vector<double>& row) {
  for (std::size_t k = std::min(grid.size(), row.size()); k-- > 0;)
    if (std::isfinite(row[k])) return grid[k];
  return -HUGE_VAL;
}

}  // namespace

EnsembleTables widened(const EnsembleTables& e) {
  EnsembleTables w = e;
  const auto& c = e.coverage;
  if (!c.phi_grid.empty()) {
    w.phi_grid = c.phi_grid;
    w.pressure_at_phi = c.pressure_at_phi;
  }
  if (!c.z_grid.empty()) {
    w.z_grid = c.z_grid;
    w.pressure_at_z = c.pressure_at_z;
    w.phi_at_z = c.phi_at_z;
  }
  return w;
}

double typical_end(const EnsembleTables& e, bool at_z) {
  const auto& grid = at_z ? e.z_grid : e.phi_grid;
  const auto& rows = at_z ? e.pressure_at_z : e.pressure_at_phi;
  std::vector<double> ends;
  for (const auto& row : rows) ends.push_back(last_with_data(grid, row));
  if (ends.empty()) return NAN;
  // Half the runs reach at least ends[size / 2]: one short run (or one long one) moves it not.
  std::sort(ends.begin(), ends.end());
  return ends[ends.size() / 2];
}

CoveringRuns covering_runs(const EnsembleTables& e, bool at_z, double lo, double hi) {
  CoveringRuns c{e, {}};
  const auto& grid = at_z ? c.tables.z_grid : c.tables.phi_grid;
  auto& rows = at_z ? c.tables.pressure_at_z : c.tables.pressure_at_phi;
  const double reach = std::min(hi, typical_end(e, at_z));
  if (!(std::isfinite(lo) && reach > lo)) return c;  // the side does not reach the range at all
  const double need = lo + kCoverShare * (reach - lo);
  std::vector<std::vector<double>> kept;
  for (std::size_t s = 0; s < rows.size(); ++s) {
    const double end = last_with_data(grid, rows[s]);
    if (end >= need - 1e-12) {
      kept.push_back(std::move(rows[s]));
      continue;
    }
    const auto id = s < e.sample_ids.size() ? e.sample_ids[s] : static_cast<std::int64_t>(s);
    c.left_out.push_back(std::isfinite(end) ? fmt::format("sample {} (data to {} {:.4g})", id,
                                                          at_z ? "Z" : "phi", end)
                                            : fmt::format("sample {} (no data)", id));
  }
  rows = std::move(kept);
  return c;
}

double coarse_step(const EnsembleTables& e) {
  const double step = grid_step(e.phi_grid);
  double coarse = NAN;
  for (double h : e.coverage.output_step)
    if (h > kCoarseFactor * step && !(h <= coarse)) coarse = h;
  return coarse;
}

std::string past_coarse_output(PoolRange& range, double* floor, bool at_z,
                               const EnsembleTables& dir, const EnsembleTables& ref,
                               double from_phi, Verdict& v) {
  const double h_dir = coarse_step(dir), h_ref = coarse_step(ref);
  if (!std::isfinite(h_dir) && !std::isfinite(h_ref)) return "";
  const double h = std::max(std::isfinite(h_dir) ? h_dir : 0.0, std::isfinite(h_ref) ? h_ref : 0.0);
  // Past the transient by one output step: no interpolated stretch reaches back into it.
  const double phi = from_phi + kStartTransient + h;
  const double start = at_z ? z_span(dir, ref, phi, HUGE_VAL).first : phi;
  v.values["coarse_step"] = h;
  if (std::isfinite(start)) {
    range.min = std::max(range.min, start);
    range.pointwise_from = std::max(range.pointwise_from, start);
    *floor = std::max(*floor, start);
  }
  return fmt::format(
      "{} output is far coarser than the grid (a run's points {:.3g} apart in phi, more than "
      "{:g} grid steps): judged from {} {:.4g}, one output step past the start's transient, "
      "across which such a run is interpolated",
      std::isfinite(h_dir) && std::isfinite(h_ref) ? "DIR's and REF's"
      : std::isfinite(h_dir)                       ? "DIR's"
                                                   : "REF's",
      h, kCoarseFactor, at_z ? "Z" : "phi", start);
}

std::string left_out_words(const CoveringRuns& d, const CoveringRuns& r, const PoolRange& range) {
  if (d.left_out.empty() && r.left_out.empty()) return "";
  auto list = [](const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? std::string("none") : out;
  };
  return fmt::format(
      "runs that end short of the range {} [{:.4g}, {:.4g}] left out: DIR {}; REF {}",
      range.variable, range.min, range.max, list(d.left_out), list(r.left_out));
}

void never_pass_narrow(Verdict& v, double asked_min, double asked_max) {
  if (v.status != "pass" || !v.values.count("range_min") || !v.values.count("range_max")) return;
  const double judged_min = v.values.at("range_min"), judged_max = v.values.at("range_max");
  const double asked = asked_max - asked_min;
  if (!(std::isfinite(asked) && asked > 0) || judged_max - judged_min >= kNarrowShare * asked)
    return;
  const char* variable =
      v.values.count("constant_z") && v.values.at("constant_z") == 1.0 ? "Z" : "phi";
  v.status = "inconclusive";
  // More runs would not widen the range: no estimate of the samples that would decide it (the
  // window scatter estimates it for verdicts with a scatter).
  v.samples_needed = NAN;
  v.values.erase("scatter_a");
  v.values.erase("scatter_b");
  v.reason = fmt::format(
      "judged over {} [{:.4g}, {:.4g}] only, less than {:g}% of the range asked [{:.4g}, "
      "{:.4g}]: no pass on so little of it; within that part: {}",
      variable, judged_min, judged_max, 100 * kNarrowShare, asked_min, asked_max, v.reason);
}

}  // namespace jam::checks
