#include "campaign/restore_starts.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "campaign/campaign_dir.hpp"
#include "campaign/campaign_lock.hpp"
#include "campaign/run_plan.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/run/thread_cpu_clock.hpp"

namespace jam {

std::size_t restore_starts(const Campaign& c, bool quiet) {
  if (c.chain_starts_from.empty()) return 0;
  const Campaign from = starts_campaign(c);
  const std::vector<PlannedRun> theirs = plan_runs(from);
  std::map<std::string, const PlannedRun*> by_name;
  for (const auto& r : theirs) by_name[r.name] = &r;
  // The runs of `from` to run again as far as their start, parents first.
  std::vector<const PlannedRun*> order;
  std::set<std::string> taken;
  const std::function<void(const PlannedRun&)> need = [&](const PlannedRun& child) {
    if (child.config.read_start.empty() || std::filesystem::exists(child.config.read_start)) return;
    const auto it = by_name.find(child.parent);
    if (it == by_name.end()) return;  // not a chained start of `from`: nothing to rewrite
    const PlannedRun& parent = *it->second;
    if (run_status(parent) != RunStatus::kDone) {
      throw CampaignError(fmt::format(
          "{}: chain_starts_from {}: the start of {} is gone and {} that leaves it is not done "
          "there (`jam campaign run` on that campaign first)",
          c.source_path, c.chain_starts_from, child.name, parent.name));
    }
    need(parent);
    if (taken.insert(parent.name).second) order.push_back(&parent);
  };
  for (const auto& r : plan_runs(c)) {
    if (r.config.read_start.empty()) continue;
    const auto it = by_name.find(r.name);
    if (it == by_name.end() || r.config.start_identity.empty()) {
      throw CampaignError(fmt::format(
          "{}: chain_starts_from {}: that campaign has no run {} starting at its chained start "
          "(a run redone from its starts must be one of its runs: same sizes, phi_init, rates, "
          "chain_phi_init, samples and seed)",
          c.source_path, c.chain_starts_from, r.name));
    }
    if (!std::filesystem::exists(r.config.read_start)) need(*it->second);
  }
  if (order.empty()) return 0;
  const CampaignLock lock(from.output);
  for (const PlannedRun* p : order) {
    // A restored snapshot holds run files only: the directories of starts may be gone too.
    for (const std::string& file : {p->config.write_start, p->config.start_cache})
      if (!file.empty())
        std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    RunControl control;
    control.checkpoint_interval_seconds = p->config.checkpoint_interval;
    control.start_only = true;
    const double cpu = thread_cpu_seconds();
    run_compression(p->config, control);
    if (!quiet) {
      fmt::print("campaign {}: the start {} left at {:g} rewritten in {} ({:.0f} CPU seconds)\n",
                 c.name, p->name, p->config.write_start_at, from.output,
                 thread_cpu_seconds() - cpu);
      std::fflush(stdout);
    }
  }
  return order.size();
}

}  // namespace jam
