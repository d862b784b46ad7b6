#include "app/campaign_command.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "sim/io/terminal_text.hpp"

namespace jam {

namespace {

/// `jam campaign converge`: the campaign file written (never over an existing file), and what
/// to run next.
int write_convergence(const CampaignArgs& a) {
  const Campaign c = read_campaign(a.file);
  const std::string text = convergence_campaign_text(c, a.converge);
  std::filesystem::path out = a.converge_out;
  if (out.empty()) {
    out = std::filesystem::path(a.file);
    out.replace_filename(out.stem().string() + "-convergence.toml");
  }
  if (std::filesystem::exists(out))
    throw CLI::ValidationError(
        "--out", fmt::format("{}: exists; move it away or name another", out.string()));
  fmt::print("{}", write_convergence_campaign(c, text, out.string()));
  return 0;
}

}  // namespace

void add_campaign_command(CLI::App& app, CampaignArgs& a) {
  CLI::App* campaign = app.add_subcommand(
      "campaign", "Run, inspect and cost ensembles of compression runs described by a TOML file");
  campaign->require_subcommand(1);
  add_campaign_run(campaign, a);  // app/campaign_run_command.cpp
  CLI::App* status = campaign->add_subcommand(
      "status", "Print what is done, partial, missing, failed or corrupt in a campaign directory");
  status->add_option("directory", a.directory, "Campaign directory (its 'output')")->required();
  status->add_flag("--json", a.json, "The same as JSON (totals, and every run's status)");
  status->footer(
      "Exit status: 0 every run is done; 1 a run failed or is corrupt; 4 runs are "
      "missing or partial (none failed); 2 the directory is not a campaign's.");
  CLI::App* import = campaign->add_subcommand(
      "import",
      "Import runs jam did not plan (open runs of any simulator, docs/cross-simulator.md) "
      "into an external campaign directory, for status, stats, check and report");
  import->add_option("directory", a.directory, "Campaign directory (new, or an external one)")
      ->required();
  import->add_option("files", a.import_files, "Run files (HDF5): open runs or jam's own")
      ->required();
  import->add_option("--phi-step", a.import_options.phi_step,
                     "Grid of packings the statistics average on (default 0.0005)");
  import->add_option("--name", a.import_options.name, "Campaign name (default: the directory's)");
  import->footer(
      "Exit status: 0 every file imported (or already there); 1 a file was set aside "
      "(the reason is printed and kept in external.toml); 2 bad input.");
  CLI::App* converge = campaign->add_subcommand(
      "converge",
      "Write the campaign file that redoes part of a campaign at a stricter integrator setting "
      "from the same starts, for `jam check convergence`");
  converge->add_option("file", a.file, "Campaign file (TOML)")->required();
  converge->add_option("--sizes", a.converge.sizes, "Sizes redone (default: every size)");
  converge->add_option("--rates", a.converge.log10_rates,
                       "Rates redone, as log10 values (default: the two slowest)");
  converge->add_option("--samples", a.converge.samples, "The campaign's first K samples")
      ->capture_default_str();
  converge
      ->add_option("--tolerance-factor", a.converge.tolerance_factor,
                   "The compression tolerance, times the campaign's strictest among the "
                   "rates redone (the error then in the largest component)")
      ->capture_default_str();
  converge
      ->add_option("--phi-stop", a.converge.phi_stop,
                   "Stop there (default: the campaign's; e.g. phi_J - 0.004 to judge only "
                   "the region below jamming)")
      ->check(CLI::Range(0.0, 1.0));
  converge->add_option("--output", a.converge.output,
                       "Its campaign directory (default: <output>-convergence)");
  converge->add_option("--out", a.converge_out,
                       "The campaign file written (default: FILE's name with -convergence)");
  CLI::App* output = campaign->add_subcommand(
      "output",
      "Print the campaign's directory (its 'output', as every jam command reads it) on one line, "
      "for scripts; the file is checked as `campaign run` checks it");
  output->add_option("file", a.file, "Campaign file (TOML)")->required();
  CLI::App* plan = campaign->add_subcommand(
      "plan", "Print the number of runs, particle-steps and estimated core-hours");
  plan->add_option("file", a.file, "Campaign file (TOML)")->required();
  plan->add_option("--scatter-from", a.plan.scatter_from,
                   "Judged campaign directories (DIR/checks.json, e.g. a pilot with few samples "
                   "of this design) whose runs' scatter predicts what the checks can decide; "
                   "default: the stored reduced result of the campaign's dimension");
  plan->add_option("--pilot", a.plan.pilot,
                   "Run K samples of every ensemble first (in <output>-pilot-K: the campaign's "
                   "first K samples, same seeds), judge them, and plan from their scatter")
      ->check(CLI::Range(2, 1000))
      ->excludes("--scatter-from");
  plan->add_flag("--probe", a.plan.probe,
                 "Price the sizes no finished run has measured by probing this machine (3 "
                 "repeats, their spread printed), not from reference/throughput.toml");
}

int run_campaign_command(const CLI::App& app, const CampaignArgs& a, const Ranks& ranks) {
  const CLI::App* campaign = app.get_subcommand("campaign");
  if (campaign->got_subcommand("run"))
    return run_campaign_run(campaign->get_subcommand("run"), a, ranks);
  if (campaign->got_subcommand("status")) {
    if (is_external_campaign(a.directory)) return print_external_status(a.directory, a.json);
    return print_campaign_status(a.directory, a.json);
  }
  if (campaign->got_subcommand("import")) {
    const ImportOutcome out = import_runs(a.directory, a.import_files, a.import_options);
    for (const auto& s : out.set_aside)
      fmt::print(stderr, "set aside {}: {}\n", visible(s.file), visible(s.reason));
    for (const auto& note : out.notes) fmt::print("{}\n", visible(note));
    fmt::print("{}: {} runs imported, {} already there, {} set aside{}\n", visible(a.directory),
               out.imported, out.already, out.set_aside.size(),
               out.repaired ? fmt::format(", {} repaired", out.repaired) : "");
    return out.set_aside.empty() ? 0 : 1;
  }
  if (campaign->got_subcommand("converge")) return write_convergence(a);
  if (campaign->got_subcommand("output")) {
    // A campaign string holds no control character (read_campaign refuses them): one line.
    fmt::print("{}\n", read_campaign(a.file).output);
    return 0;
  }
  return design::print_plan_stage(read_campaign(a.file), a.plan, a.run, ranks);
}

}  // namespace jam
