#include "design/plan_stage.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "design/pilot.hpp"
#include "design/plan_decidability.hpp"

namespace jam::design {
namespace {

/// DIR/checks.json of each judged campaign directory.
std::vector<std::string> checks_files_of(const std::vector<std::string>& directories) {
  std::vector<std::string> out;
  for (const auto& d : directories)
    out.push_back((std::filesystem::path(d) / "checks.json").string());
  return out;
}

}  // namespace

int print_plan_stage(const Campaign& c, const PlanRequest& r, const CampaignRunOptions& run,
                     const Ranks& ranks) {
  // The variance model first, so that a bad --scatter-from is refused before any output.
  ScatterModel model;
  std::string no_model;
  try {
    std::vector<std::string> sources = r.scatter_from.empty() ? default_scatter_sources(c.run.dim)
                                                              : checks_files_of(r.scatter_from);
    if (r.pilot > 0) {
      const Campaign pilot = pilot_campaign(c, r.pilot);
      fmt::print("pilot: {} samples of every ensemble in {}\n", r.pilot, pilot.output);
      sources = checks_files_of({run_pilot(pilot, run, ranks)});
      if (ranks.rank != 0) return 0;
    }
    model = fit_scatter_model(sources, c.question.states_range() ? "asked" : "");
  } catch (const std::exception& e) {
    // A file the user named is an error; the stored default missing is only a gap.
    if (r.pilot > 0) throw std::runtime_error(e.what());
    if (!r.scatter_from.empty())
      throw std::runtime_error(fmt::format("--scatter-from: {}", e.what()));
    no_model = e.what();
  }
  Throughput speed;
  print_campaign_plan(c, &speed, r.probe);
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

}  // namespace jam::design
