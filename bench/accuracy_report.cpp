// The report of `jam bench accuracy`: CSV of every method, a markdown table per dimension and
// rate, the reference's convergence, and the headline: wall time to reach 1% and 0.1% error
// for jam's default (SimConfig's integrator at the rate's default tolerance or dt), jam's best
// and LAMMPS's best setting.
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
const SimConfig kJamDefaults;

std::string label(const Method& m) {
  if (m.integrator == "verlet") return fmt::format("{} verlet Q={:g}", m.engine, m.quality_factor);
  if (m.integrator == "chebyshev")
    return fmt::format("{} chebyshev tol {:g}", m.engine, m.tolerance);
  return fmt::format("{} {}", m.engine, m.integrator);
}

/// The fastest method of the selection whose error is at most `target`.
std::optional<Method> fastest(const AccuracyResult& r, int dim, double rate, double target,
                              const std::function<bool(const Method&)>& select) {
  std::optional<Method> best;
  for (const auto& m : r.methods) {
    if (m.dim != dim || m.rate != rate || m.is_reference || m.engine == "jam-process" ||
        m.start != "relaxed" || !select(m))
      continue;
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

/// The headline: whole processes at the campaigns' output grid, per dimension, rate and start.
std::string process_table(const AccuracyResult& r) {
  std::string md =
      "## Whole processes at the campaigns' output grid\n\n"
      "`jam sim --read-lammps-data START --relax 0 --phi-step 0.0005` to phi_J + 0.015, as a "
      "user runs it: wall time from spawn to exit (start-up, reading the start, every output "
      "point, the run file), median over seeds. LAMMPS: the whole `lmp` process on the same "
      "relaxed start (inertial at Q, dt 0.8 of its stability bound, thermo every 0.05 t0: "
      "denser than the grid). Error: max over the three packings of |mean p/p_ref - 1|, "
      "against the reference from the same start.\n\n"
      "| D | rate | start | method | wall (s) | max error | ratio to jam defaults |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& ref : r.references) {
    const Method* defaults = nullptr;
    for (const auto& m : r.methods)
      if (m.dim == ref.dim && m.rate == ref.rate && m.start == ref.start &&
          m.engine == "jam-process" && m.integrator == "defaults")
        defaults = &m;
    for (const auto& m : r.methods) {
      if (m.dim != ref.dim || m.rate != ref.rate || m.start != ref.start) continue;
      if (m.engine != "jam-process" && m.engine != "lammps") continue;
      const std::string name = m.engine == "lammps"
                                   ? fmt::format("LAMMPS Q {:g}, dt {:g}", m.quality_factor, m.dt)
                                   : "jam " + m.integrator;
      const std::string ratio =
          defaults && defaults->process_wall_median > 0
              ? fmt::format("{:.1f}x", m.process_wall_median / defaults->process_wall_median)
              : "-";
      md += fmt::format("| {} | {:g} | {} | {} | {:.3g} | {:.2e} ± {:.0e} | {} |\n", m.dim, m.rate,
                        m.start, name, m.process_wall_median, m.max_error, m.max_error_se, ratio);
    }
  }
  return md + "\n";
}

}  // namespace

void write_accuracy_report(const AccuracyOptions& o, const AccuracyResult& r) {
  fs::create_directories(o.out_dir);
  std::string csv =
      "dim,rate,start,engine,integrator,q,dt,wall_median_s,process_wall_median_s,error_below,error_"
      "at,error_above,se_below,"
      "se_at,se_above,max_error,max_error_se,tolerance\n";
  for (const auto& m : r.methods) {
    csv += fmt::format(
        "{},{:g},{},{},{},{:g},{:g},{:.6g},{:.6g},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},"
        "{:.4g},{:.4g},{:g}\n",
        m.dim, m.rate, m.start, m.engine, m.integrator, m.quality_factor, m.dt, m.wall_median,
        m.process_wall_median, m.error[0], m.error[1], m.error[2], m.error_se[0], m.error_se[1],
        m.error_se[2], m.max_error, m.max_error_se, m.tolerance);
  }
  std::string md = fmt::format(
      "# Accuracy: wall time against the error of the pressure\n\n`{}`\n\nMachine: {}. Date: "
      "{}.\nN = {}, {} seeds (relaxed starts), {} runs at once. Errors: |mean over seeds of "
      "p/p_ref - 1| at phi_J - 0.01, phi_J, phi_J + 0.015 (phi_J the paper's), +- the standard "
      "error; 'max' is the largest of the three. Wall: median over seeds; of the whole process in "
      "the first table, of the compression alone in the others (jam: the stepping loop; LAMMPS: "
      "its Loop time). Each whole process (jam sim, lmp) ran {} times, its times the medians "
      "of those runs.\n\n",
      o.command, machine_description(), utc_now(), o.n, o.seeds, o.jobs, o.process_repeats);

  md += process_table(r);
  md += "## Time to 1% and 0.1% error (the stepping loop alone)\n\n" +
        fmt::format(
            "| D | rate | target | jam default ({} at the rate's default tolerance, "
            "100 rate within [1e-4, 3e-3]) | jam best | LAMMPS best | LAMMPS best / jam best |\n"
            "|---|---|---|---|---|---|---|\n",
            kJamDefaults.resolved_integrator());
  for (const auto& ref : r.references) {
    if (ref.start != "relaxed") continue;
    for (double target : {0.01, 0.001}) {
      // The default at this rate: its integrator, at its default tolerance or dt.
      SimConfig at_rate = kJamDefaults;
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
      "| D | rate | start | phi | p_ref | ratio of differences (4 = order 2) | "
      "|p_R - p(h/4)|/p_R |\n"
      "|---|---|---|---|---|---|---|\n";
  for (const auto& ref : r.references)
    for (int k = 0; k < 3; ++k)
      md += fmt::format("| {} | {:g} | {} | {:.4f} | {:.6g} | {:.2f} | {:.2g} |\n", ref.dim,
                        ref.rate, ref.start, ref.phi[k], ref.p[k], ref.ratio[k], ref.remaining[k]);
  for (const auto& ref : r.references) {
    md += fmt::format(
        "\n## {}D, rate {:g}, {} start\n\n| method | dt | wall (s) | error below | at | above "
        "| max |\n|---|---|---|---|---|---|---|\n",
        ref.dim, ref.rate, ref.start);
    for (const auto& m : r.methods) {
      if (m.dim != ref.dim || m.rate != ref.rate || m.start != ref.start) continue;
      const std::string name = m.is_reference              ? "jam " + m.integrator
                               : m.engine == "jam-process" ? "jam process, " + m.integrator
                                                           : label(m);
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
