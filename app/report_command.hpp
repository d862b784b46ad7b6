#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace jam {

struct ReportArgs {
  std::string directory;
  std::string out;  // default reports/<campaign name>
  bool quiet = false;
};

/// Registers `jam report DIR`: the HTML report of a campaign, drawn by reports/jam_report.py.
void add_report_command(CLI::App& app, ReportArgs& args);

int run_report_command(const ReportArgs& args);

}  // namespace jam
