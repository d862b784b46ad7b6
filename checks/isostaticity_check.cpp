// Isostaticity at the jamming point. A packing of frictionless spheres jams when its contacts
// first suffice to hold every non-rattling particle: in a periodic box N_nr such particles
// need N_c = D (N_nr - 1) + 1 contacts (the D global translations are not constrained; Goodrich,
// Liu & Nagel, PRL 109, 095704 (2012)), so at phi_J the non-rattlers' mean contact number is
//   Z_nr,iso = 2 N_c / N_nr = 2 D - 2 (D - 1) / N_nr.
// When the runs removed their rattlers (rattlers = true: stats.h5 holds
// constant_phi/contacts_per_particle_no_rattlers_samples), that count is judged: the clean
// statement. N_nr of each run is not in stats.h5, so N stands for it: Z_nr,iso is then too high
// by 2 (D - 1) f_r / (N (1 - f_r)) for a rattler fraction f_r: at most 8.1e-4 of Z's 4 (a
// relative 2.0e-4) at 2D N = 256 with the largest f_r measured, 9.4%, less at larger N
// (docs/statistics-and-checks.md#isostaticity): far below the margin and the runs' scatter.
// Otherwise the contacts over every particle, rattlers included, are judged against
// the same count with N_nr = N; rattlers hold no contacts in the quasistatic limit, so there
// <Z> / Z_iso - 1 is about minus their share of the particles. A finite rate adds the contacts
// of the flow. The margin holds both; a count further off is an error of the contacts, of the
// jamming points or of the claim that the slowest rate is near the quasistatic limit.
//
// Per (N, phi_init), at the slowest rate whose runs looked for their jamming points, each run k
// gives d_k = Z_k(phi_Ji,k) / Z_iso(N) - 1: its own contacts at its own jamming point, linear
// between the two grid packings around it. Their mean is judged against the margin with
// Student's t (checks/margin.hpp: pass when effects beyond it are excluded, fail when the
// effect surely exceeds it, else inconclusive); Bonferroni over the (N, phi_init), as zeta.
#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "checks/checks.hpp"
#include "checks/margin.hpp"

namespace jam::checks {
namespace {

/// Z_k at phi: linear between the grid points around it; NaN outside the grid or where either
/// point has no value.
double contacts_at(const std::vector<double>& grid, const std::vector<double>& z, double phi) {
  const auto hi = std::lower_bound(grid.begin(), grid.end(), phi);
  if (!std::isfinite(phi) || hi == grid.begin() || hi == grid.end()) return NAN;
  const auto k = static_cast<std::size_t>(hi - grid.begin());
  const double t = (phi - grid[k - 1]) / (grid[k] - grid[k - 1]);
  return z[k - 1] + t * (z[k] - z[k - 1]);
}

/// The contacts a verdict judges: the non-rattlers' when the runs stored them.
struct JudgedCount {
  const std::vector<std::vector<double>>& z;  // [sample][point] of e.phi_grid
  bool without_rattlers;
};
JudgedCount judged_count(const EnsembleTables& e) {
  if (!e.z_nr_samples_at_phi.empty()) return {e.z_nr_samples_at_phi, true};
  return {e.z_samples_at_phi, false};
}

/// d_k of every run of e with a jamming point and its contacts z around it.
std::vector<double> isostatic_deviations(const EnsembleTables& e,
                                         const std::vector<std::vector<double>>& z_samples,
                                         double z_iso) {
  std::vector<double> out;
  for (std::size_t j = 0; j < e.jamming_points.size() && j < e.jamming_sample_ids.size(); ++j) {
    const auto row = std::find(e.sample_ids.begin(), e.sample_ids.end(), e.jamming_sample_ids[j]);
    if (row == e.sample_ids.end()) continue;
    const auto r = static_cast<std::size_t>(row - e.sample_ids.begin());
    if (r >= z_samples.size()) continue;
    const double z = contacts_at(e.phi_grid, z_samples[r], e.jamming_points[j]);
    if (std::isfinite(z)) out.push_back(z / z_iso - 1.0);
  }
  return out;
}

Verdict judge_isostatic(const EnsembleTables& e, int dim, Levels levels, const CheckOptions& o) {
  Verdict v;
  v.check = "isostaticity";
  const JudgedCount count = judged_count(e);
  const char* counted = count.without_rattlers ? "without rattlers" : "with rattlers";
  v.case_name =
      fmt::format("{}: <Z> {} at the jamming points vs isostatic", case_label(e), counted);
  v.statistic_name = "|mean Z(phi_Ji) / Z_iso - 1| / standard error (Student t)";
  // 2D - 2(D - 1)/N_nr with N for N_nr (the file's opening comment bounds the error).
  const double z_iso = 2.0 * dim - 2.0 * (dim - 1) / static_cast<double>(e.n);
  const std::vector<double> d = isostatic_deviations(e, count.z, z_iso);
  v.values = {{"n", static_cast<double>(e.n)},
              {"phi_init", e.phi_init},
              {"log10_rate", e.log10_rate},
              {"z_isostatic", z_iso},
              {"without_rattlers", count.without_rattlers ? 1.0 : 0.0},
              {"samples_a", static_cast<double>(d.size())}};  // the table's samples cell
  if (d.size() < 2) {
    v.status = "inconclusive";
    v.reason = fmt::format(
        "{} of {} runs have a jamming point inside the grid of their contacts {}: at least 2 "
        "are needed",
        d.size(), e.jamming_points.size(), counted);
    return v;
  }
  const double n = static_cast<double>(d.size());
  double mean = 0, var = 0;
  for (double x : d) mean += x / n;
  for (double x : d) var += (x - mean) * (x - mean) / (n - 1);
  const double se = std::sqrt(var / n), dof = n - 1;
  auto bounds = [&](Levels l) {
    return std::pair{gsl_cdf_tdist_Qinv(l.detect / 2, dof), gsl_cdf_tdist_Qinv(l.pass, dof)};
  };
  const auto [t_detect, t_pass] = bounds(levels);
  v.statistic = se > 0 ? std::abs(mean) / se : HUGE_VAL;
  v.threshold = t_detect;
  v.detectable = t_detect * se;
  v.estimate = mean;
  decide(v, v.statistic > t_detect, std::abs(mean) + t_pass * se, std::abs(mean) - t_detect * se,
         o.margin("isostaticity"));
  v.reason += fmt::format(
      " (<Z> {} at phi_Ji {:.4g}, isostatic {:.4g}{}: {} +- {} over {} runs; t at {:.0f} "
      "degrees of freedom, alpha {:.3g})",
      counted, z_iso * (1 + mean), z_iso,
      count.without_rattlers ? "" : " (the runs stored no count without rattlers)",
      effect_text(v, mean, true), effect_text(v, se), d.size(), dof, levels.detect);
  v.values["z_mean"] = z_iso * (1 + mean);
  if (v.status == "inconclusive") {
    const auto [t_detect_next, t_pass_next] = bounds(o.for_estimate(levels));
    v.samples_needed =
        samples_to_decide({mean}, {t_pass_next * se}, {t_detect_next * se}, v.margin, d.size());
    if (std::isfinite(v.samples_needed))
      v.reason += fmt::format("; about {:.0f} runs would decide it (estimate)", v.samples_needed);
  }
  return v;
}

}  // namespace

std::vector<Verdict> isostaticity_check(const StatsData& d, const CheckOptions& o) {
  // The slowest rate with jamming points and contacts of each (N, phi_init): the nearest to the
  // quasistatic limit, where the isostatic count holds.
  std::map<std::pair<std::int64_t, double>, const EnsembleTables*> slowest;
  for (const auto& e : d.ensembles) {
    if (e.jamming_points.empty() || judged_count(e).z.empty()) continue;
    auto& s = slowest[{e.n, e.phi_init}];
    if (!s || e.log10_rate < s->log10_rate) s = &e;
  }
  if (slowest.empty()) {
    return {inconclusive("isostaticity", "all",
                         "no ensemble of stats.h5 has both jamming points and contacts per "
                         "sample (runs look for their jamming points with jamming_point = true)")};
  }
  const Levels levels{o.alpha / static_cast<double>(slowest.size()), o.alpha};
  std::vector<Verdict> out;
  for (const auto& [key, e] : slowest) out.push_back(judge_isostatic(*e, d.dim, levels, o));
  return out;
}

}  // namespace jam::checks
