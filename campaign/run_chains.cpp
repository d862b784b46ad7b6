#include "campaign/run_chains.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "campaign/campaign_dir.hpp"
#include "sim/io/chain_start.hpp"
#include "sim/io/checkpoint.hpp"

namespace jam {
namespace {

/// Marks the parents that needed chained runs cannot do without (start-only when a parent is
/// done); holds back the children of failed parents.
void add_parents(const std::vector<PlannedRun>& plan, const std::map<std::string, std::size_t>& at,
                 bool retry_failed, std::vector<bool>& needed, std::vector<bool>& start_only,
                 std::vector<std::string>& notes) {
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k < plan.size(); ++k) {
      if (!needed[k] || plan[k].parent.empty()) continue;
      const std::size_t p = at.at(plan[k].parent);
      if (needed[p]) continue;  // it runs first and leaves the start again
      const SimConfig& c = plan[k].config;
      const std::string problem = chain_start_problem(c.read_start, c.start_identity);
      if (problem.empty()) continue;
      changed = true;
      const RunStatus status = run_status(plan[p]);
      if (status == RunStatus::kDone) {
        needed[p] = true;
        start_only[p] = true;
        notes.push_back(
            fmt::format("{} runs again to {:g} only, for the start of {} ({}); its "
                        "run file is kept",
                        plan[p].name, plan[p].config.write_start_at, plan[k].name, problem));
        continue;
      }
      if (status == RunStatus::kFailed && !retry_failed) {
        needed[k] = false;
        notes.push_back(fmt::format("{} waits for {}, which failed (--retry-failed redoes it)",
                                    plan[k].name, plan[p].name));
        continue;
      }
      needed[p] = true;
      std::error_code ec;
      std::filesystem::remove(checkpoint_path(plan[p].config.out), ec);
      notes.push_back(fmt::format("{} is redone: the start of {} is not usable ({})", plan[p].name,
                                  plan[k].name, problem));
    }
  }
}

}  // namespace

RunTasks plan_tasks(const std::vector<PlannedRun>& plan, const std::vector<std::int64_t>& pending,
                    bool retry_failed) {
  std::map<std::string, std::size_t> at;
  for (std::size_t k = 0; k < plan.size(); ++k) at[plan[k].name] = k;
  std::vector<bool> needed(plan.size(), false);
  for (const auto k : pending) needed[static_cast<std::size_t>(k)] = true;
  RunTasks out;
  out.start_only.assign(plan.size(), false);
  add_parents(plan, at, retry_failed, needed, out.start_only, out.notes);

  // A needed run belongs to the task of its oldest needed ancestor; depth orders the task.
  std::map<std::size_t, std::vector<std::pair<int, std::size_t>>> by_root;
  for (std::size_t k = 0; k < plan.size(); ++k) {
    if (!needed[k]) continue;
    std::size_t root = k;
    int depth = 0;
    while (!plan[root].parent.empty() && needed[at.at(plan[root].parent)]) {
      root = at.at(plan[root].parent);
      ++depth;
    }
    by_root[root].push_back({depth, k});
  }
  for (auto& [root, members] : by_root) {
    std::sort(members.begin(), members.end());
    std::vector<std::size_t> task;
    for (const auto& [depth, k] : members) task.push_back(k);
    out.tasks.push_back(std::move(task));
  }
  // Longest first, by the same estimate the queue balances with.
  std::stable_sort(out.tasks.begin(), out.tasks.end(), [&](const auto& a, const auto& b) {
    return task_cost(plan, out, a) > task_cost(plan, out, b);
  });
  return out;
}

double task_cost(const std::vector<PlannedRun>& plan, const RunTasks& tasks,
                 const std::vector<std::size_t>& task) {
  double cost = 0.0;
  for (const auto k : task) {
    cost += tasks.start_only[k] ? plan[k].start_particle_steps : plan[k].estimated_particle_steps;
  }
  return cost;
}

std::vector<std::int64_t> tasks_for_broadcast(const RunTasks& tasks) {
  std::vector<std::int64_t> codes;
  for (const auto& t : tasks.tasks) {
    for (const auto k : t) {
      const auto index = static_cast<std::int64_t>(k);
      codes.push_back(tasks.start_only[k] ? start_only_code(index) : index);
    }
    codes.push_back(kEndOfTask);
  }
  return codes;
}

RunTasks tasks_from_broadcast(const std::vector<std::int64_t>& codes, std::size_t runs) {
  RunTasks out;
  out.start_only.assign(runs, false);
  out.tasks.emplace_back();
  for (const auto c : codes) {
    if (c == kEndOfTask) {
      out.tasks.emplace_back();
    } else if (c < kEndOfTask) {
      const auto index = static_cast<std::size_t>(kEndOfTask - 1 - c);  // start_only_code's inverse
      out.start_only[index] = true;
      out.tasks.back().push_back(index);
    } else {
      out.tasks.back().push_back(static_cast<std::size_t>(c));
    }
  }
  out.tasks.pop_back();
  return out;
}

}  // namespace jam
