#pragma once
// The MPI calls of a campaign (ranks.cpp), in a module of their own (jam-mpi.so) that jam
// loads only when an MPI launcher started it. Linking MPI into jam itself costs every process
// the loading of OpenMPI's runtime (libmpi, open-pal, open-rte, hwloc, libevent, udev: about
// 2 ms of CPU, a twentieth of a 2D N = 4096 run at rate 1e-3; docs/performance.md, "Start-up"),
// although a single run, a report or a test never uses it.
//
// A table of plain functions with a C name, looked up once (dlsym); `abi` changes whenever the
// table does, so that a module from another build is refused instead of called wrongly.
#include <cstdint>

namespace jam {

inline constexpr int kMpiModuleAbi = 1;
inline constexpr const char* kMpiModuleSymbol = "jam_mpi_module";

struct MpiModule {
  int abi;
  /// MPI_Init_thread asking for MPI_THREAD_MULTIPLE; rank, size and whether it was granted.
  void (*start)(int* argc, char*** argv, int* rank, int* size, int* thread_multiple);
  void (*stop)();
  /// MPI_Abort on MPI_COMM_WORLD when it has more than one rank.
  void (*abort)(int code);
  /// Rank 0's count, then rank 0's values (the buffer holds `count` on every rank).
  void (*broadcast_count)(long long* count);
  void (*broadcast_values)(std::int64_t* values, int count);
  int (*max_over_ranks)(int value);
  int (*sum_over_ranks)(int value);
  void (*send)(std::int64_t value, int destination, int tag);
  std::int64_t (*receive)(int source, int tag);
  /// The next message from any rank with any tag.
  void (*receive_any)(std::int64_t* value, int* source, int* tag);
  void (*barrier)();
};

}  // namespace jam
