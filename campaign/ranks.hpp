#pragma once
// The processes sharing a campaign: MPI ranks when jam was started by mpirun (or srun) and
// built with MPI, otherwise a single process. MPI is initialised only when a launcher's
// environment is present, so a plain `jam` never pays for (or depends on) an MPI runtime.
#include <cstdint>
#include <vector>

namespace jam {

struct Ranks {
  int rank = 0;
  int size = 1;
};

/// Whether this jam was built with MPI (`jam --version` says so).
bool built_with_mpi();

/// Starts MPI when launched under an MPI launcher; returns this process's rank and the size.
/// A jam built without MPI and started as one of several processes exits with status 2 and
/// one line saying so, instead of running the whole campaign in every process.
Ranks start_ranks(int* argc, char*** argv);
void stop_ranks();
/// Ends every rank with exit status `code` after an error on this one (MPI_Abort), so that no
/// rank waits for ever in a collective the failed rank will never reach; returns (does
/// nothing) without MPI or with one rank.
void abort_ranks(int code);

/// Rank 0's values on every rank (identity with one rank).
std::vector<std::int64_t> broadcast_from_root(std::vector<std::int64_t> values);
/// Largest value over the ranks.
int max_over_ranks(int value);
/// Sum over the ranks.
int sum_over_ranks(int value);
void barrier();

/// Whether threads other than the main one may call MPI (MPI_THREAD_MULTIPLE was granted).
bool threads_may_use_mpi();

/// Point-to-point messages of one int64 (run_queue.hpp's protocol).
void send_value(std::int64_t value, int destination, int tag);
std::int64_t receive_value(int source, int tag);
struct Message {
  int source = 0, tag = 0;
  std::int64_t value = 0;
};
/// The next message from any rank with any tag.
Message receive_any();

}  // namespace jam
