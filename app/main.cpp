// jam: compression-driven jamming of bidisperse soft spheres. One executable, subcommands.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <exception>
#include <string>
#include <system_error>

#include "app/bench_command.hpp"
#include "app/campaign_command.hpp"
#include "app/check_command.hpp"
#include "app/import_command.hpp"
#include "app/pipeline_command.hpp"
#include "app/report_command.hpp"
#include "app/schema_command.hpp"
#include "app/sim_command.hpp"
#include "app/stats_command.hpp"
#include "app/validate_command.hpp"
#include "sim/io/install_paths.hpp"
#include "sim/io/terminal_text.hpp"
#include "sim/run/stop_signal.hpp"
#include "sim/simd.hpp"
#include "sim/version.hpp"

namespace {
/// The version and what this build can do: MPI (campaigns over ranks), OpenMP (--threads),
/// AVX2 forms of the hot loops and whether this processor runs them.
std::string version_text() {
#if defined(_OPENMP)
  const char* openmp = "yes";
#else
  const char* openmp = "no (--threads 1 only)";
#endif
#if defined(JAM_AVX2_FORMS)
  const char* avx2 = jam::cpu_has_avx2() ? "yes" : "built, not on this processor";
#else
  const char* avx2 = "no";
#endif
  return fmt::format("jam {}\nMPI: {}\nOpenMP: {}\nAVX2: {}", jam::kVersion,
                     jam::built_with_mpi() ? "yes" : "no (rebuild with libopenmpi-dev installed)",
                     openmp, avx2);
}
}  // namespace

int main(int argc, char** argv) {
  const jam::Ranks ranks = jam::start_ranks(&argc, &argv);
  struct StopRanks {
    ~StopRanks() { jam::stop_ranks(); }
  } stop_ranks_at_exit;

  CLI::App app{"jam: compression-driven jamming of bidisperse soft spheres"};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  jam::SimConfig sim_config;
  jam::add_sim_command(app, sim_config);
  jam::CampaignArgs campaign_args;
  jam::add_campaign_command(app, campaign_args);
  jam::StatsArgs stats_args;
  jam::add_stats_command(app, stats_args);
  jam::CheckArgs check_args;
  jam::add_check_command(app, check_args);
  jam::ImportRequest import_request;
  jam::add_import_command(app, import_request);
  jam::ReportArgs report_args;
  jam::add_report_command(app, report_args);
  jam::PipelineArgs pipeline_args;
  jam::add_pipeline_command(app, pipeline_args);
  jam::ValidateArgs validate_args;
  jam::add_validate_command(app, validate_args);
  jam::SchemaArgs schema_args;
  jam::add_schema_command(app, schema_args);
  jam::BenchArgs bench_args;
  bench_args.throughput.reference_dir = jam::data_path("reference/lammps").string();
  bench_args.accuracy.reference_dir = jam::data_path("reference/lammps").string();
  jam::add_bench_command(app, bench_args);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::Success& e) {
    // An option that did all that was asked while parsing (`jam check --list`).
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, naming the option: CLI11's messages already do.
    fmt::print(stderr, "jam: error: {}\n", jam::visible(e.what()));
    return 2;
  }
  auto run_subcommand = [&]() {
    if (app.got_subcommand("sim")) return jam::run_sim_command(sim_config);
    if (app.got_subcommand("campaign")) return jam::run_campaign_command(app, campaign_args, ranks);
    if (app.got_subcommand("stats")) return jam::run_stats_command(stats_args);
    if (app.got_subcommand("check")) return jam::run_check_command(check_args);
    if (app.got_subcommand("import")) return jam::run_import_command(import_request);
    if (app.got_subcommand("report")) return jam::run_report_command(report_args);
    if (app.got_subcommand("bench")) return jam::run_bench_command(app, bench_args, argc, argv);
    if (app.got_subcommand("validate")) return jam::run_validate_command(validate_args);
    if (app.got_subcommand("schema")) return jam::run_schema_command(schema_args);
    if (app.got_subcommand("pipeline")) return jam::run_pipeline_command(pipeline_args, ranks);
    return 0;
  };
  try {
    const int status = run_subcommand();
    // Standard output is buffered: a full disk under `jam ... > file` shows only when it is
    // flushed, and a summary silently cut short must not exit 0.
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      throw std::system_error(errno, std::generic_category(), "cannot write to file");
    }
    return status;
  } catch (const std::system_error& e) {
    // fmt's own words for a failed print, "cannot write to file: ...", name no file: the file
    // is standard output (redirected to a full disk, say).
    const std::string what = e.what();
    const bool print_failed = what.rfind("cannot write to file", 0) == 0;
    fmt::print(stderr, "jam: error: {}\n",
               print_failed ? "cannot write to standard output: " + e.code().message()
                            : jam::visible(what));
    jam::abort_ranks(2);
    return 2;
  } catch (const jam::Interrupted& e) {
    // A stop asked for (SIGINT, SIGTERM) before an output was published: nothing written.
    fmt::print(stderr, "jam: {}\n", e.what());
    return 130;
  } catch (const std::exception& e) {
    // The tool could not do what was asked (bad input, a missing or unreadable file, a full
    // disk): exit status 2 in every subcommand, apart from the results a command reports
    // itself (a failed verdict, a failed run: 1). Control characters of a file name or value
    // are shown, not sent to the terminal.
    fmt::print(stderr, "jam: error: {}\n", jam::visible(e.what()));
    // Under MPI the other ranks may be waiting for this one in a collective: end them all,
    // with the status a single process would have had.
    std::fflush(stdout);
    std::fflush(stderr);
    jam::abort_ranks(2);
    return 2;
  }
  return 0;
}
