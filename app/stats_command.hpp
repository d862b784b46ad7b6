#pragma once
#include <CLI/CLI.hpp>
#include <optional>

#include "stats/campaign_stats.hpp"

namespace jam {

struct StatsArgs {
  std::string directory;
  stats::StatsOptions options;
  // absent: not given
  std::optional<double> fit_phi_init, fix_phi_j, fix_rate_exponent, fix_inv_znu;
  bool fix_paper_exponents = false;
  bool fix_paper_rate_exponent = false;
  bool refit = false;
  // The verdicts the fit uses (stats/fit_verdicts.hpp): "auto" DIR's verdict files where
  // present, "none" none.
  std::string fit_verdicts = "auto";
};

/// Registers `jam stats DIR`.
void add_stats_command(CLI::App& app, StatsArgs& args);

int run_stats_command(const StatsArgs& args);

}  // namespace jam
