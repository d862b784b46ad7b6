#include "app/check_command.hpp"

#include <fmt/format.h>

#include "app/check_options.hpp"
#include "checks/check_registry.hpp"

namespace jam {

void add_check_command(CLI::App& app, CheckArgs& a) {
  // The accepted names and the help text come from the registry (checks/check_registry.hpp).
  const std::vector<std::string> names = checks::command_names();
  std::string listed, not_in_all;
  for (const auto& name : names) listed += (listed.empty() ? "" : ", ") + name;
  for (const auto& e : checks::check_registry())
    if (!e.in_all) not_in_all += (not_in_all.empty() ? "" : ", ") + std::string(e.name);
  CLI::App* c = app.add_subcommand(
      "check", fmt::format("Statistical verdicts from DIR/stats.h5: {}. Each verdict is pass (the "
                           "data exclude effects beyond the margin), fail (the data exclude "
                           "effects at or below the margin: it surely exceeds it) or inconclusive",
                           listed));
  c->footer(
      "Exit status: 0 every verdict passes; 1 a verdict fails (expected failures named in the "
      "campaign file's expected_failures apart); 3 none fails but one is inconclusive; 2 the "
      "check could not run (usage error, missing or corrupt stats.h5).");
  c->option_defaults()->always_capture_default();
  // --json before --list: flags take effect in the order they are declared, and --list prints
  // as it is taken (before the required NAME and DIR are asked for).
  c->add_flag("--json", a.list_json, "--list: as JSON (what checks.json carries under checks)");
  c->add_flag_callback(
      "--list",
      [&a] {
        fmt::print("{}", a.list_json ? checks::registry_json() : checks::registry_table());
        throw CLI::Success();
      },
      "List the registered checks: kind, default margin and why, member of all, report figure");
  c->add_option("name", a.check.name,
                fmt::format("{} (all: all but {})", listed,
                            not_in_all.empty() ? std::string("none") : not_in_all))
      ->required()
      ->check(CLI::IsMember(names));
  c->add_option("directory", a.check.directory, "Campaign directory (after `jam stats`)")
      ->required();
  // --alpha, --permutations, --phi-min, --phi-max, --phi-j, --region-near, --region-far,
  // --margin, --reference-dir, --no-lmp, --with-lammps: the table `jam pipeline` shares
  // (design/judging_options.cpp).
  add_judging_options(c, a.check.judging);
  c->add_option("--set-a", a.check.set_a,
                "finite_size: first run set, e.g. n=1024,phi_init=0.6,rate=-4");
  c->add_option("--set-b", a.check.set_b, "finite_size: second run set");
  c->add_option("--against", a.check.against,
                "regression, chain, convergence, compare: the directory holding the stats.h5 "
                "to judge DIR against (regression: a baseline, e.g. a stored result in "
                "reference/results/; chain: the unchained control; convergence: the stricter "
                "re-runs `jam campaign converge` wrote; compare: REF, the reference "
                "simulator's campaign)");
  c->add_option("--tolerance", a.check.regression.tolerance,
                "regression: largest relative difference of rerun samples (0: bitwise)");
  c->add_flag("--regenerate-reference", a.check.regenerate,
              "lammps: run lmp and rewrite the stored LAMMPS result in --reference-dir");
}

int run_check_command(const CheckArgs& a) {
  return design::run_check_stage(a.check);
}

}  // namespace jam
