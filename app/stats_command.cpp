#include "app/stats_command.hpp"

#include <fmt/format.h>

#include <cmath>

#include "design/stats_stage.hpp"
#include "sim/model/paper_values.hpp"

namespace jam {

void add_stats_command(CLI::App& app, StatsArgs& a) {
  CLI::App* s = app.add_subcommand(
      "stats",
      "Average a campaign at constant phi and Z, fit the critical scaling, write DIR/stats.h5");
  s->option_defaults()->always_capture_default();
  s->add_option("directory", a.directory, "Campaign directory (its 'output')")->required();
  s->add_option("--z-step", a.options.z_step, "Grid spacing in Z for averages at constant Z");
  s->add_flag("--no-rattlers", a.options.no_rattlers,
              "Average at constant Z with rattlers removed (runs must store it)");
  s->add_flag("--pool-sizes", a.options.pool_sizes,
              "Average all sizes together (after the finite-size check passed)");
  s->add_option("--fit-phi-init", a.fit_phi_init,
                "phi_init of the fitted ensembles (optional; default: the lowest)")
      ->always_capture_default(false);
  s->add_option("--order", a.options.order, "Polynomial order of ln f(x)");
  s->add_option("--fix-phi-j", a.fix_phi_j, "Hold phi_J at this value (optional)");
  s->add_option("--fix-q", a.fix_rate_exponent, "Hold q at this value (optional)");
  s->add_option("--fix-inv-znu", a.fix_inv_znu, "Hold 1/(z nu) at this value (optional)");
  s->add_flag("--fix-paper-exponents", a.fix_paper_exponents,
              "Hold q and 1/(z nu) at the paper's values for the dimension");
  s->add_flag("--fix-paper-q", a.fix_paper_rate_exponent,
              "Hold q at the paper's value for the dimension (phi_J and 1/(z nu) fitted)");
  s->add_flag(
      "--no-fit", [&a](std::int64_t) { a.options.fit = false; }, "Averages only");
  s->add_option("--fit-verdicts", a.fit_verdicts,
                "The verdicts the fit uses, a declared input recorded in stats.h5: auto (DIR's "
                "checks.json: phi_init verdicts clear the rates of a fitted phi_init above the "
                "lowest, finite_size verdicts allow the paper's protocol to pool sizes; "
                "checks-phi_init.json) or none")
      ->check(CLI::IsMember({"auto", "none"}));
  s->add_flag("--refit", a.refit,
              "Refit the averages already in DIR/stats.h5 instead of reading the runs (for "
              "stored results whose runs are not kept); jamming points carry over");
}

int run_stats_command(const StatsArgs& a) {
  stats::StatsOptions o = a.options;
  if (a.fit_phi_init) o.fit_phi_init = *a.fit_phi_init;
  auto held = [](const char* option, const std::optional<double>& v, double hi) {
    if (v && !(std::isfinite(*v) && *v > 0 && *v < hi)) {
      throw CLI::ValidationError(option, fmt::format("{:g}: must be in (0, {:g})", *v, hi));
    }
    return v;
  };
  o.fixed_phi_j = held("--fix-phi-j", a.fix_phi_j, 1.5);
  o.fixed_rate_exponent = held("--fix-q", a.fix_rate_exponent, 1.0);
  o.fixed_inv_znu = held("--fix-inv-znu", a.fix_inv_znu, 1e3);
  // A refit reads the stored averages; it cannot average the sizes together (that needs the
  // runs), and fitting the largest size alone under --pool-sizes would say nothing of it.
  if (a.refit && o.pool_sizes)
    throw std::runtime_error(
        "--pool-sizes with --refit: a refit keeps the stored file's averages (pooled only if "
        "they were); average again with `jam stats DIR --pool-sizes`");
  if (o.order < 0 || o.order > 9) {
    throw std::runtime_error(fmt::format("--order {}: must be in 0..9", o.order));
  }
  // Z lies in [0, 2D]; a step below 1e-4 resolves nothing the samples hold, and each grid point
  // costs memory in every run's curve.
  if (!(o.z_step >= 1e-4 && o.z_step <= 1))
    throw std::runtime_error(fmt::format("--z-step {:g}: must be in [1e-4, 1]", o.z_step));
  if (a.fix_paper_exponents || a.fix_paper_rate_exponent) {
    // Needs the dimension: read it with the data.
    stats::StatsOptions averages_only;
    averages_only.fit = false;
    const auto dim = a.refit ? stats::refit_campaign_stats(a.directory, averages_only).data.dim
                             : stats::read_campaign_runs(a.directory).dim;
    o.fixed_rate_exponent = paper_values(dim).rate_exponent();
    if (a.fix_paper_exponents) o.fixed_inv_znu = paper_values(dim).inv_znu();
  }
  // The verdicts the fit may use, declared here (read through checks/verdict_file.hpp), never
  // found by stats/ itself.
  if (a.fit_verdicts == "auto") o.verdicts = design::declared_fit_verdicts(a.directory);
  design::write_campaign_stats(a.directory, o, a.refit);
  return 0;
}

}  // namespace jam
