#pragma once
// What one worker of `jam campaign run` takes at a time: a task, the pending runs of one chain
// in order (a chained run after the run it continues from, campaign_file.hpp chain_phi_init),
// or a single run when the campaign has no chains. So a chained run always waits for its
// parent, on one rank, whatever the sharding or the number of MPI ranks (shards and ranks
// take whole tasks; shard_of keeps a sample's runs in one share).
#include <cstdint>
#include <string>
#include <vector>

#include "campaign/run_plan.hpp"

namespace jam {

struct RunTasks {
  std::vector<std::vector<std::size_t>> tasks;  // plan indices, parents first; longest first
  std::vector<std::string> notes;               // what was added or held back, and why
  // Per plan index: a done run that runs again only to the start its child lost, up to the
  // start's packing (RunControl::start_only), its run file kept.
  std::vector<bool> start_only;
};

/// Groups `pending` (plan indices) into tasks. A pending chained run whose start is missing or
/// unsound needs its parent again. A parent that is done runs again only as far as the start
/// (the same trajectory, so the same start, for a fraction of its cost; its run file stays);
/// its own start, when lost as well, is rewritten so in turn. A parent not done joins the task
/// (redone from its start, its checkpoint removed, since it may have passed the start's packing
/// already), unless its last attempt failed and failed runs are not retried; then the child is
/// held back.
RunTasks plan_tasks(const std::vector<PlannedRun>& plan, const std::vector<std::int64_t>& pending,
                    bool retry_failed);

/// The estimated particle-steps of a task (its runs' together, a start-only run's to its start).
double task_cost(const std::vector<PlannedRun>& plan, const RunTasks& tasks,
                 const std::vector<std::size_t>& task);

/// Tasks as one array of integers for an MPI broadcast, and back (`runs`: the plan's size). Each
/// task is its runs' indices followed by kEndOfTask; a run done only to its start (start_only)
/// is written as start_only_code(k), a number below kEndOfTask, so that one array carries both.
inline constexpr std::int64_t kEndOfTask = -1;
constexpr std::int64_t start_only_code(std::int64_t run) { return kEndOfTask - 1 - run; }
std::vector<std::int64_t> tasks_for_broadcast(const RunTasks& tasks);
RunTasks tasks_from_broadcast(const std::vector<std::int64_t>& codes, std::size_t runs);

}  // namespace jam
