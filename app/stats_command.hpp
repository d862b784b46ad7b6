#pragma once
#include <CLI/CLI.hpp>

#include "stats/campaign_stats.hpp"

namespace jam {

struct StatsArgs {
  std::string directory;
  stats::StatsOptions options;
  double fit_phi_init = -1.0, fix_phi_j = -1.0, fix_q = -1.0, fix_inv_znu = -1.0;
  bool fix_paper_exponents = false;
  bool fix_paper_q = false;
  bool refit = false;
};

/// Registers `jam stats DIR`.
void add_stats_command(CLI::App& app, StatsArgs& args);

int run_stats_command(const StatsArgs& args);

}  // namespace jam
