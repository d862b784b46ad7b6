#include "app/validate_command.hpp"

#include <fmt/format.h>

#include <exception>

#include "sim/io/open_run.hpp"
#include "sim/io/terminal_text.hpp"

namespace jam {

void add_validate_command(CLI::App& app, ValidateArgs& args) {
  CLI::App* v = app.add_subcommand(
      "validate",
      "Check run files as the open run format says (docs/cross-simulator.md), before importing "
      "them: one line per file, `ok` or the field and value refused");
  v->add_option("RUN", args.runs, "Open runs or run files of jam's own")->required();
}

int run_validate_command(const ValidateArgs& args) {
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
