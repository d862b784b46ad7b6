#include "app/campaign_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <tuple>
#include <utility>

#include "app/until_decided.hpp"
#include "design/pilot.hpp"
#include "design/plan_decidability.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/terminal_text.hpp"

namespace jam {

namespace {

/// `jam campaign converge`: the campaign file written (never over an existing file), and what
/// to run next.
int write_convergence_campaign(const CampaignArgs& a) {
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
  {
    AtomicFile file(out.string());
    std::fputs(text.c_str(), file.stream());
    file.commit();
  }
  const Campaign written = read_campaign(out.string());
  fmt::print(
      "wrote {}: {} runs of {} redone\nthen:\n  jam campaign run {}\n  jam stats {}\n"
      "  jam check convergence {} --against {}\n",
      out.string(),
      written.samples * written.sizes.size() * written.phi_init.size() * written.log10_rates.size(),
      c.name, out.string(), written.output, c.output, written.output);
  return 0;
}

}  // namespace

void add_campaign_command(CLI::App& app, CampaignArgs& a) {
  CLI::App* campaign = app.add_subcommand(
      "campaign", "Run, inspect and cost ensembles of compression runs described by a TOML file");
  campaign->require_subcommand(1);
  CLI::App* run = campaign->add_subcommand(
      "run", "Run every missing run (resumes partial ones); under mpirun the ranks share them");
  run->option_defaults()->always_capture_default();
  run->add_option("file", a.file, "Campaign file (TOML, see reference/campaigns/)")->required();
  run->add_option("--jobs", a.run.jobs, "Runs at once per process (0 = all cores)");
  run->add_flag("--retry-failed", a.run.retry_failed, "Also redo runs whose last attempt failed");
  run->add_flag("--quiet", a.run.quiet, "No progress display and no summary");
  run->add_option("--log-every", a.run.log_seconds,
                  "Without a terminal (a batch log): a progress line every this many seconds")
      ->check(CLI::Range(0.1, 86400.0));
  run->add_option("--shard", a.shard,
                  "K/N: run only the K-th of N disjoint shares of the campaign (whole samples, "
                  "balanced by cost; K from 1), e.g. one per Slurm array task; together the N "
                  "shares are the whole campaign, bitwise. 'auto': this Slurm array task's "
                  "share, whatever the array's first index (--array=0-31 or 1-32, steps too)");
  run->add_flag("--force", a.run.force,
                "Run even runs beyond the per-run limits on steps, output points and memory");
  run->add_flag("--until-decided", a.until_decided,
                "Then judge the checks, add samples to the ensembles of undecided verdicts and "
                "judge again, until every verdict is decided or --budget is spent (alpha "
                "spent over the looks: docs/statistics-and-checks.md#until-decided)");
  run->add_option("--budget", a.until.budget_core_hours,
                  "--until-decided: core-hours all runs of the campaign may take, in all");
  run->add_option("--alpha", a.until.alpha,
                  "--until-decided: false-alarm rate of each check over all looks (default: the "
                  "campaign file's [question] alpha, else 0.05)")
      ->check(CLI::Range(1e-6, 0.5));
  run->add_option("--phi-min", a.until.phi_min,
                  "--until-decided: the range asked from this packing, judged as the region "
                  "\"asked\" (default: the campaign file's [question] phi_min); with a range "
                  "asked only its verdicts drive the samples added")
      ->always_capture_default(false);
  run->add_option("--phi-max", a.until.phi_max,
                  "--until-decided: the range asked up to this packing (default: [question] "
                  "phi_max)")
      ->always_capture_default(false);
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
  plan->add_option("--scatter-from", a.scatter_from,
                   "Judged campaign directories (DIR/checks.json, e.g. a pilot with few samples "
                   "of this design) whose runs' scatter predicts what the checks can decide; "
                   "default: the stored reduced result of the campaign's dimension");
  plan->add_option("--pilot", a.pilot,
                   "Run K samples of every ensemble first (in <output>-pilot-K: the campaign's "
                   "first K samples, same seeds), judge them, and plan from their scatter")
      ->check(CLI::Range(2, 1000))
      ->excludes("--scatter-from");
  plan->add_flag("--probe", a.probe,
                 "Price the sizes no finished run has measured by probing this machine (3 "
                 "repeats, their spread printed), not from reference/throughput.toml");
}

namespace {

/// A whole number from the environment variable `name` (`fallback` when unset).
long slurm_number(const char* name, long fallback) {
  const char* text = std::getenv(name);
  if (!text) {
    if (fallback >= 0) return fallback;
    throw CLI::ValidationError("--shard",
                               fmt::format("auto: {} is not set (not a Slurm array task)", name));
  }
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 0) {
    throw CLI::ValidationError("--shard",
                               fmt::format("auto: {}={} is not a whole number", name, text));
  }
  return v;
}

/// --shard K/N (K from 1) or `auto`: the share of this Slurm array task, K = (ID - MIN) / STEP
/// + 1 of N = COUNT, so that arrays numbered from 0 or 1, or with a step, all work.
std::pair<int, int> parse_shard(const std::string& shard) {
  if (shard == "auto") {
    const long id = slurm_number("SLURM_ARRAY_TASK_ID", -1);
    const long count = slurm_number("SLURM_ARRAY_TASK_COUNT", -1);
    const long first = slurm_number("SLURM_ARRAY_TASK_MIN", -1);
    const long step = std::max(1L, slurm_number("SLURM_ARRAY_TASK_STEP", 1));
    const long k = (id - first) / step + 1;
    if (id < first || (id - first) % step != 0 || count < 1 || k > count || count > 1000000) {
      throw CLI::ValidationError(
          "--shard", fmt::format("auto: task {} of an array of {} from {} in steps of {} is not "
                                 "one of its tasks",
                                 id, count, first, step));
    }
    return {static_cast<int>(k), static_cast<int>(count)};
  }
  int k = 0, n = 0;
  char rest = 0;
  if (std::sscanf(shard.c_str(), "%d/%d%c", &k, &n, &rest) != 2 || n < 1 || k < 1 || k > n) {
    throw CLI::ValidationError(
        "--shard", shard +
                       ": must read K/N with 1 <= K <= N, e.g. 3/8 (K counts from 1; for a "
                       "Slurm array numbered from 0, give --shard auto)");
  }
  return {k, n};
}

/// DIR/checks.json of each judged campaign directory.
std::vector<std::string> checks_files_of(const std::vector<std::string>& directories) {
  std::vector<std::string> out;
  for (const auto& d : directories)
    out.push_back((std::filesystem::path(d) / "checks.json").string());
  return out;
}

}  // namespace

int run_campaign_command(const CLI::App& app, const CampaignArgs& a, const Ranks& ranks) {
  const CLI::App* campaign = app.get_subcommand("campaign");
  if (campaign->got_subcommand("run")) {
    CampaignRunOptions options = a.run;
    if (!a.shard.empty()) std::tie(options.shard, options.shards) = parse_shard(a.shard);
    const CLI::App* run = campaign->get_subcommand("run");
    if (a.until_decided) {
      try {
        validate_until_decided(a.until);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("--budget", e.what());
      }
      const Campaign c = read_campaign(a.file);
      UntilDecidedOptions until = a.until;
      // The campaign's question is the default; the command line's --alpha overrides it.
      if (!run->count("--alpha") && c.question.alpha) until.alpha = *c.question.alpha;
      try {
        sequence_question(c, until);  // a range that is none: one line, before any run
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError(e.what());
      }
      return run_until_decided(c, options, until, ranks);
    }
    if (run->count("--budget") || run->count("--alpha") || run->count("--phi-min") ||
        run->count("--phi-max"))
      throw CLI::ValidationError(
          "--budget", "--budget, --alpha, --phi-min and --phi-max go with --until-decided");
    return run_campaign(read_campaign(a.file), options, ranks);
  }
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
  if (campaign->got_subcommand("converge")) return write_convergence_campaign(a);
  if (campaign->got_subcommand("output")) {
    // A campaign string holds no control character (read_campaign refuses them): one line.
    fmt::print("{}\n", read_campaign(a.file).output);
    return 0;
  }
  const Campaign c = read_campaign(a.file);
  // The variance model first, so that a bad --scatter-from is refused before any output.
  ScatterModel model;
  std::string no_model;
  try {
    std::vector<std::string> sources = a.scatter_from.empty() ? default_scatter_sources(c.run.dim)
                                                              : checks_files_of(a.scatter_from);
    if (a.pilot > 0) {
      const Campaign pilot = pilot_campaign(c, a.pilot);
      fmt::print("pilot: {} samples of every ensemble in {}\n", a.pilot, pilot.output);
      sources = checks_files_of({run_pilot(pilot, a.run, ranks)});
      if (ranks.rank != 0) return 0;
    }
    model = fit_scatter_model(sources, c.question.states_range() ? "asked" : "");
  } catch (const std::exception& e) {
    // A file the user named is an error; the stored default missing is only a gap.
    if (a.pilot > 0) throw std::runtime_error(e.what());
    if (!a.scatter_from.empty()) throw CLI::ValidationError("--scatter-from", e.what());
    no_model = e.what();
  }
  Throughput speed;
  print_campaign_plan(c, &speed, a.probe);
  print_phi_init_findings(c);
  if (!c.chain_starts_from.empty())
    fmt::print(
        "  what it can decide: runs redone from {}'s starts are judged against it (`jam check "
        "convergence {} --against {}`), not on their own\n",
        c.chain_starts_from, c.chain_starts_from, c.output);
  else if (no_model.empty())
    print_decidability(c, model, speed);
  else
    fmt::print("  what it can decide: no variance model ({})\n", no_model);
  return 0;
}

}  // namespace jam
