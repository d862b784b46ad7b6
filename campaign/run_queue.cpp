#include "campaign/run_queue.hpp"

#include <algorithm>
#include <numeric>

namespace jam {

RunQueue::RunQueue(std::vector<std::int64_t> pending, const std::vector<double>& costs,
                   const Ranks& ranks, int local_workers, const std::atomic<bool>* stop)
    : ranks_(ranks), stop_(stop) {
  dynamic_ = ranks.size == 1 || threads_may_use_mpi();
  double total = 0.0;
  for (auto k : pending) total += costs[static_cast<std::size_t>(k)];
  if (dynamic_) {
    local_estimate_ = total / ranks.size;
    if (ranks.rank == 0) queue_ = std::move(pending);
    // Every rank learns how many workers the others have; rank 0 serves the remote ones.
    const int all_workers = sum_over_ranks(local_workers);
    if (ranks.rank == 0 && ranks.size > 1) {
      dispatcher_ = std::thread([this, remote = all_workers - local_workers] { dispatch(remote); });
    }
    return;
  }
  // Longest-processing-time split in advance: deterministic, within a few percent of the best
  // balance when the estimates are right.
  std::vector<double> load(static_cast<std::size_t>(ranks.size), 0.0);
  for (auto k : pending) {
    const auto least =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[least] += costs[static_cast<std::size_t>(k)];
    if (static_cast<int>(least) == ranks.rank) queue_.push_back(k);
  }
  local_estimate_ = load[static_cast<std::size_t>(ranks.rank)];
}

RunQueue::~RunQueue() {
  if (dispatcher_.joinable()) dispatcher_.join();
}

std::optional<std::size_t> RunQueue::take() {
  if (stop_ && stop_->load()) return std::nullopt;
  const std::size_t slot = next_.fetch_add(1);
  if (slot >= queue_.size()) return std::nullopt;
  return static_cast<std::size_t>(queue_[slot]);
}

std::optional<std::size_t> RunQueue::next(int worker) {
  if (!dynamic_ || ranks_.rank == 0) return take();
  send_value(kReplyBase + worker, 0, kRequest);
  const std::int64_t index = receive_value(0, kReplyBase + worker);
  if (index < 0) return std::nullopt;
  return static_cast<std::size_t>(index);
}

void RunQueue::quit(int worker) {
  if (dynamic_ && ranks_.rank != 0) send_value(worker, 0, kQuit);
}

void RunQueue::dispatch(int remote_workers) {
  int finished = 0;
  while (finished < remote_workers) {
    const Message m = receive_any();
    if (m.tag == kQuit) {
      ++finished;
      continue;
    }
    const std::optional<std::size_t> index = take();
    send_value(index ? static_cast<std::int64_t>(*index) : -1, m.source, static_cast<int>(m.value));
    if (!index) ++finished;
  }
}

}  // namespace jam
