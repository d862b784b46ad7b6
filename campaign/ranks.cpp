#include "campaign/ranks.hpp"

#include <cstdio>
#include <cstdlib>

#ifdef JAM_HAVE_MPI
#include <mpi.h>
#endif

namespace jam {
namespace {
#ifdef JAM_HAVE_MPI
bool mpi_active = false;
bool mpi_multiple = false;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(v)) return true;
  }
  return false;
}
#endif

/// The number of processes an MPI launcher started, as its environment says (1 when it says
/// nothing): OpenMPI's mpirun, PMI and PMIx launchers (MPICH's, srun --mpi=pmi2 or pmix).
long launched_processes() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* value = std::getenv(v)) {
      char* end = nullptr;
      const long n = std::strtol(value, &end, 10);
      if (end != value && n > 1) return n;
    }
  }
  return 1;
}
}  // namespace

bool built_with_mpi() {
#ifdef JAM_HAVE_MPI
  return true;
#else
  return false;
#endif
}

Ranks start_ranks([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
  Ranks r;
  if (!built_with_mpi() && launched_processes() > 1) {
    // Each process would run the whole campaign alone and collide with the others.
    std::fprintf(stderr,
                 "jam: error: started as one of %ld processes (mpirun or srun), but this jam was "
                 "built without MPI; install OpenMPI's headers (libopenmpi-dev) and rebuild, or "
                 "run one process\n",
                 launched_processes());
    std::exit(2);
  }
#ifdef JAM_HAVE_MPI
  if (launched_by_mpi()) {
    // Worker threads ask rank 0 for runs themselves (run_queue.hpp): ask for full thread
    // support, and fall back to a split made in advance when the library does not give it.
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided);
    mpi_multiple = provided >= MPI_THREAD_MULTIPLE;
    MPI_Comm_rank(MPI_COMM_WORLD, &r.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &r.size);
    mpi_active = true;
  }
#endif
  return r;
}

void stop_ranks() {
#ifdef JAM_HAVE_MPI
  if (mpi_active) MPI_Finalize();
  mpi_active = false;
#endif
}

void abort_ranks([[maybe_unused]] int code) {
#ifdef JAM_HAVE_MPI
  int size = 1;
  if (mpi_active) MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
}

std::vector<std::int64_t> broadcast_from_root(std::vector<std::int64_t> values) {
#ifdef JAM_HAVE_MPI
  if (mpi_active) {
    long long count = static_cast<long long>(values.size());
    MPI_Bcast(&count, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    values.resize(static_cast<std::size_t>(count));
    MPI_Bcast(values.data(), static_cast<int>(count), MPI_INT64_T, 0, MPI_COMM_WORLD);
  }
#endif
  return values;
}

int max_over_ranks(int value) {
#ifdef JAM_HAVE_MPI
  if (mpi_active) {
    int result = value;
    MPI_Allreduce(&value, &result, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return result;
  }
#endif
  return value;
}

int sum_over_ranks(int value) {
#ifdef JAM_HAVE_MPI
  if (mpi_active) {
    int result = value;
    MPI_Allreduce(&value, &result, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    return result;
  }
#endif
  return value;
}

bool threads_may_use_mpi() {
#ifdef JAM_HAVE_MPI
  return mpi_active && mpi_multiple;
#else
  return false;
#endif
}

void send_value([[maybe_unused]] std::int64_t value, [[maybe_unused]] int destination,
                [[maybe_unused]] int tag) {
#ifdef JAM_HAVE_MPI
  if (mpi_active) MPI_Send(&value, 1, MPI_INT64_T, destination, tag, MPI_COMM_WORLD);
#endif
}

std::int64_t receive_value([[maybe_unused]] int source, [[maybe_unused]] int tag) {
  std::int64_t value = -1;
#ifdef JAM_HAVE_MPI
  if (mpi_active) MPI_Recv(&value, 1, MPI_INT64_T, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
#endif
  return value;
}

Message receive_any() {
  Message m;
#ifdef JAM_HAVE_MPI
  if (mpi_active) {
    MPI_Status status;
    MPI_Recv(&m.value, 1, MPI_INT64_T, MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
    m.source = status.MPI_SOURCE;
    m.tag = status.MPI_TAG;
  }
#endif
  return m;
}

void barrier() {
#ifdef JAM_HAVE_MPI
  if (mpi_active) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

}  // namespace jam
