// The report of `jam bench accuracy`: CSV of every method, a markdown table per dimension and
// rate, the reference's convergence, and the headline: wall time to reach 1% and 0.1% error
// for jam's default (Euler, dt 0.01), jam's best and LAMMPS's best setting.
#include <fmt/format.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <optional>

#include "bench/accuracy.hpp"
#include "bench/report_files.hpp"
#include "sim/run/sim_config.hpp"

namespace jam::bench {
namespace fs = std::filesystem;
namespace {

// The default integrator and dt of `jam sim` and of campaigns: the "jam default" column.
const SimConfig kDefaults;

std::string label(const Method& m) {
  if (m.integrator == "verlet") return fmt::format("{} verlet Q={:g}", m.engine, m.q);
  if (m.integrator == "chebyshev")
    return fmt::format("{} chebyshev tol {:g}", m.engine, m.tolerance);
  return fmt::format("{} {}", m.engine, m.integrator);
}

/// The fastest method of the selection whose error is at most `target`.
std::optional<Method> fastest(const AccuracyResult& r, int dim, double rate, double target,
                              const std::function<bool(const Method&)>& select) {
  std::optional<Method> best;
  for (const auto& m : r.methods) {
    if (m.dim != dim || m.rate != rate || m.is_reference || !select(m)) continue;
    if (m.max_error > target) continue;
    if (!best || m.wall_median < best->wall_median) best = m;
  }
  return best;
}

std::string cell(const std::optional<Method>& m) {
  if (!m) return "not reached";
  if (m->integrator == "chebyshev") return fmt::format("{:.3g} s ({})", m->wall_median, label(*m));
  return fmt::format("{:.3g} s ({}, dt {:g})", m->wall_median, label(*m), m->dt);
}

}  // namespace

void write_accuracy_report(const AccuracyOptions& o, const AccuracyResult& r) {
  fs::create_directories(o.out_dir);
  std::string csv =
      "dim,rate,engine,integrator,q,dt,wall_median_s,error_below,error_at,error_above,se_below,"
      "se_at,se_above,max_error,max_error_se,tolerance\n";
  for (const auto& m : r.methods) {
    csv += fmt::format(
        "{},{:g},{},{},{:g},{:g},{:.6g},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},"
        "{:.4g},{:.4g},{:g}\n",
        m.dim, m.rate, m.engine, m.integrator, m.q, m.dt, m.wall_median, m.error[0], m.error[1],
        m.error[2], m.error_se[0], m.error_se[1], m.error_se[2], m.max_error, m.max_error_se,
        m.tolerance);
  }
  std::string md = fmt::format(
      "# Accuracy: wall time against the error of the pressure\n\n`{}`\n\nMachine: {}. Date: "
      "{}.\nN = {}, {} seeds (relaxed starts), {} runs at once. Errors: |mean over seeds of "
      "p/p_ref - 1| at phi_J - 0.01, phi_J, phi_J + 0.015 (phi_J the paper's), +- the standard "
      "error; 'max' is the largest of the three. Wall: median over seeds of the compression "
      "(jam: the stepping loop; LAMMPS: its Loop time).\n\n",
      o.command, machine_description(), utc_now(), o.n, o.seeds, o.jobs);

  md += "## Time to 1% and 0.1% error\n\n" +
        fmt::format(
            "| D | rate | target | jam default ({} at the rate's default tolerance, "
            "100 rate within [1e-4, 1e-2]) | jam best | LAMMPS best | LAMMPS best / jam best |\n"
            "|---|---|---|---|---|---|---|\n",
            kDefaults.resolved_integrator());
  for (const auto& ref : r.references) {
    for (double target : {0.01, 0.001}) {
      // The default at this rate: its integrator, at its default tolerance or dt.
      SimConfig at_rate = kDefaults;
      at_rate.compression_rate = ref.rate;
      auto is_default = [&](const Method& m) {
        if (m.engine != "jam" || m.integrator != at_rate.resolved_integrator()) return false;
        return is_adaptive_integrator(m.integrator)
                   ? std::abs(m.tolerance / at_rate.resolved_tolerance() - 1.0) < 1e-12
                   : std::abs(m.dt - at_rate.dt) < 1e-12;
      };
      const auto def = fastest(r, ref.dim, ref.rate, target, is_default);
      const bool default_run =
          fastest(r, ref.dim, ref.rate, std::numeric_limits<double>::infinity(), is_default)
              .has_value();
      const auto jam =
          fastest(r, ref.dim, ref.rate, target, [](const Method& m) { return m.engine == "jam"; });
      const auto lmp =
          fastest(r, ref.dim, ref.rate, target, [](const Method& m) { return m.engine != "jam"; });
      md += fmt::format(
          "| {} | {:g} | {:g}% | {} | {} | {} | {} |\n", ref.dim, ref.rate, 100 * target,
          default_run ? cell(def) : "not run", cell(jam), cell(lmp),
          jam && lmp ? fmt::format("{:.1f}", lmp->wall_median / jam->wall_median) : "-");
    }
  }
  md +=
      "\n## Reference (Heun at h, h/2, h/4; Richardson from the last two)\n\n"
      "| D | rate | phi | p_ref | ratio of differences (4 = order 2) | |p_R - p(h/4)|/p_R |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& ref : r.references)
    for (int k = 0; k < 3; ++k)
      md += fmt::format("| {} | {:g} | {:.4f} | {:.6g} | {:.2f} | {:.2g} |\n", ref.dim, ref.rate,
                        ref.phi[k], ref.p[k], ref.ratio[k], ref.remaining[k]);
  for (const auto& ref : r.references) {
    md += fmt::format(
        "\n## {}D, rate {:g}\n\n| method | dt | wall (s) | error below | at | above | max |\n"
        "|---|---|---|---|---|---|---|\n",
        ref.dim, ref.rate);
    for (const auto& m : r.methods) {
      if (m.dim != ref.dim || m.rate != ref.rate) continue;
      const std::string name = m.is_reference ? "jam " + m.integrator : label(m);
      md += fmt::format(
          "| {} | {:g} | {:.3g} | {:.2e} ± {:.0e} | {:.2e} ± {:.0e} | {:.2e} ± {:.0e} | {:.2e} "
          "|\n",
          name, m.dt, m.wall_median, m.error[0], m.error_se[0], m.error[1], m.error_se[1],
          m.error[2], m.error_se[2], m.max_error);
    }
  }
  const std::string base = (fs::path(o.out_dir) / "accuracy").string();
  write_text_file(base + ".csv", csv);
  write_text_file(base + ".md", md);
  plot("accuracy", base + ".csv", base + ".png");
}

}  // namespace jam::bench
