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

/// Each file judged by `ok_line` (a line after "FILE: ok: "), or its reason printed: one line
/// per file that starts with the file's name (HDF5's own message on a file that is not HDF5
/// at all does not, so it gets the name in front). Status 1 when any file is refused.
template <class OkLine>
int validate_each(const std::vector<std::string>& paths, OkLine ok_line) {
  int status = 0;
  for (const std::string& path : paths) {
    try {
      fmt::print("{}: ok: {}\n", visible(path), ok_line(path));
    } catch (const std::exception& e) {
      const std::string why = e.what();
      fmt::print("{}\n", visible(why.starts_with(path) ? why : path + ": " + why));
      status = 1;
    }
  }
  return status;
}

}  // namespace

int run_validate_command(const ValidateArgs& args) {
  if (args.checks)  // as every reader of a checks.json reads it
    return validate_each(args.runs, [](const std::string& path) {
      const checks::VerdictFile f = checks::read_verdict_file(path);
      return fmt::format("schema {}, {} verdicts", f.schema_version, f.verdicts.size());
    });
  if (args.stats)  // as every reader of a stats.h5 reads it
    return validate_each(args.runs, [](const std::string& path) {
      const stats::StatsFileSummary s = stats::check_stats_file(path);
      return fmt::format("schema {}, campaign {}, {} ensembles", s.schema_version,
                         visible(s.campaign), s.ensembles);
    });
  return validate_each(args.runs, [](const std::string& path) {
    const OpenRun r = read_open_run(path);
    const auto& phi = r.packing_fraction;
    return fmt::format(
        "{} {}, D {}, N {}, rate {:.4g}, phi_init {:.6g}, sample {}, {} points (phi {:.6g} to "
        "{:.6g})",
        visible(r.simulator), visible(r.simulator_version), r.dim, r.n, r.compression_rate,
        r.phi_init, r.sample, phi.size(), phi.front(), phi.back());
  });
}

}  // namespace jam
