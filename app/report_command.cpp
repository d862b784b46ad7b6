#include "app/report_command.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "sim/io/install_paths.hpp"
#include "sim/io/process.hpp"

namespace jam {
namespace fs = std::filesystem;

void add_report_command(CLI::App& app, ReportArgs& a) {
  CLI::App* c = app.add_subcommand(
      "report",
      "HTML report with figures of a campaign directory (after `jam stats` and `jam check`)");
  c->add_option("directory", a.directory, "Campaign directory")->required();
  c->add_option("--out", a.out, "Report directory (default reports/<campaign name>)");
  c->add_flag("--quiet", a.quiet, "No summary on stdout");
}

namespace {

// The plotting code: <prefix>/share/jam/reports when installed, else reports/ of the source
// tree (install_paths.hpp); JAM_REPORTS_DIR in the environment points elsewhere.
std::string report_script() {
  const char* from_env = std::getenv("JAM_REPORTS_DIR");
  const fs::path dir = from_env ? fs::path(from_env) : data_path("reports");
  const fs::path script = dir / "jam_report.py";
  if (!fs::exists(script))
    throw std::runtime_error(
        fmt::format("report script {} not found (set JAM_REPORTS_DIR to the reports/ folder)",
                    script.string()));
  return script.string();
}

// Debian's interpreter has python3-matplotlib and python3-h5py; another python3 first on the
// PATH (a virtualenv, pyenv) usually has neither. JAM_PYTHON overrides.
std::string python() {
  if (const char* from_env = std::getenv("JAM_PYTHON")) return from_env;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

}  // namespace

int run_report_command(const ReportArgs& a) {
  std::vector<std::string> args{python(), report_script(), a.directory};
  if (!a.out.empty()) {
    args.push_back("--out");
    args.push_back(a.out);
  }
  if (a.quiet) args.push_back("--quiet");
  // Under `jam pipeline` a stop is passed on as SIGINT: the Python removes its temporary
  // directory and exits 130, so no half-drawn report is left (without the handlers installed,
  // as for `jam report`, there is never one to pass on).
  ProcessOptions o;
  o.pass_stop_on = true;
  return run_program(args, o);
}

}  // namespace jam
