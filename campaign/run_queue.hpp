#pragma once
// Hands out a campaign's pending runs, longest first, to whichever worker asks next: the
// threads of this process and, under MPI, the worker threads of every rank, so that no rank
// idles while another still has a queue (a split made in advance cannot know which runs will
// take longer than estimated). Rank 0 holds the queue; a dispatcher thread there answers the
// other ranks' requests. This needs MPI_THREAD_MULTIPLE; without it each rank takes a
// longest-processing-time share decided in advance.
//
// Protocol (tags): a worker of rank r sends kRequest with the tag it will read the answer on
// (kReplyBase + its number); rank 0 answers with a plan index, or -1 when nothing is left (or a
// stop was requested). A worker that stops before being told -1 sends kQuit. Rank 0 stops
// dispatching when every remote worker has been told -1 or has quit.
#include <atomic>
#include <cstdint>
#include <optional>
#include <thread>
#include <vector>

#include "campaign/ranks.hpp"

namespace jam {

class RunQueue {
 public:
  /// pending: plan indices, longest first (rank 0's list, the same on every rank);
  /// costs: the estimated cost of each plan index (for the split in advance).
  RunQueue(std::vector<std::int64_t> pending, const std::vector<double>& costs, const Ranks& ranks,
           int local_workers, const std::atomic<bool>* stop);
  RunQueue(const RunQueue&) = delete;
  RunQueue& operator=(const RunQueue&) = delete;
  ~RunQueue();

  /// The next plan index for local worker `worker`, or nothing when no run is left.
  std::optional<std::size_t> next(int worker);
  /// Worker `worker` stops early (a stop request, an unwritable disk): rank 0 stops waiting for
  /// it. Not needed after next() returned nothing.
  void quit(int worker);
  /// Whether runs are handed out as workers ask (false: a split made in advance).
  bool dynamic() const { return dynamic_; }
  /// The estimated cost of the runs this process can expect to do (for its ETA).
  double local_estimate() const { return local_estimate_; }

 private:
  static constexpr int kRequest = 1, kQuit = 2, kReplyBase = 100;
  std::optional<std::size_t> take();
  void dispatch(int remote_workers);

  std::vector<std::int64_t> queue_;
  std::atomic<std::size_t> next_{0};
  Ranks ranks_;
  const std::atomic<bool>* stop_;
  bool dynamic_ = false;
  double local_estimate_ = 0.0;
  std::thread dispatcher_;
};

}  // namespace jam
