#include "app/validate_command.hpp"

#include <fmt/format.h>

#include <exception>

#include "checks/verdict_file.hpp"
#include "sim/io/open_run.hpp"
#include "sim/io/terminal_text.hpp"
#include "stats/stats_schema.hpp"

namespace jam {

void add_validate_command(CLI::App& app, ValidateArgs& args) {
  CLI::App* v = app.add_subcommand(
      "validate",
      "Check run files as the open run format says (docs/cross-simulator.md), before importing "
      "them: one line per file, `ok` or the field and value refused");
  v->add_option("RUN", args.runs, "Open runs or run files of jam's own")->required();
  v->add_flag("--checks", args.checks,
              "The files are verdict files (checks.json), checked against "
              "reference/schema/checks.toml as every reader of them checks them");
  v->add_flag("--stats", args.stats,
              "The files are statistics (stats.h5), checked against "
              "reference/schema/stats.toml as every reader of them checks them")
      ->excludes("--checks");
}

namespace {

/// `jam validate --checks`: each file read as every reader of a checks.json reads it.
int validate_verdict_files(const ValidateArgs& args) {
  int status = 0;
  for (const std::string& path : args.runs) {
    try {
      const checks::VerdictFile f = checks::read_verdict_file(path);
      fmt::print("{}: ok: schema {}, {} verdicts\n", visible(path), f.schema_version,
                 f.verdicts.size());
    } catch (const std::exception& e) {
      fmt::print("{}\n", visible(e.what()));  // the reasons start with the file's name
      status = 1;
    }
  }
  return status;
}

/// `jam validate --stats`: each file read as every reader of a stats.h5 reads it.
int validate_stats_files(const ValidateArgs& args) {
  int status = 0;
  for (const std::string& path : args.runs) {
    try {
      const stats::StatsFileSummary s = stats::check_stats_file(path);
      fmt::print("{}: ok: schema {}, campaign {}, {} ensembles\n", visible(path), s.schema_version,
                 visible(s.campaign), s.ensembles);
    } catch (const std::exception& e) {
      fmt::print("{}\n", visible(e.what()));  // the reasons start with the file's name
      status = 1;
    }
  }
  return status;
}

}  // namespace

int run_validate_command(const ValidateArgs& args) {
  if (args.checks) return validate_verdict_files(args);
  if (args.stats) return validate_stats_files(args);
  int status = 0;
  for (const std::string& path : args.runs) {
    try {
      const OpenRun r = read_open_run(path);
      const auto& phi = r.packing_fraction;
      fmt::print(
          "{}: ok: {} {}, D {}, N {}, rate {:.4g}, phi_init {:.6g}, sample {}, {} points "
          "(phi {:.6g} to {:.6g})\n",
          visible(path), visible(r.simulator), visible(r.simulator_version), r.dim, r.n,
          r.compression_rate, r.phi_init, r.sample, phi.size(), phi.front(), phi.back());
    } catch (const std::exception& e) {
      // read_open_run's reasons start with the file's name.
      fmt::print("{}\n", visible(e.what()));
      status = 1;
    }
  }
  return status;
}

}  // namespace jam
