#include "campaign/ranks.hpp"

#include <cstdlib>

#ifdef JAM_HAVE_MPI
#include <mpi.h>
#endif

namespace jam {
#ifdef JAM_HAVE_MPI
namespace {
bool mpi_active = false;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(v)) return true;
  }
  return false;
}
}  // namespace
#endif

Ranks start_ranks([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
  Ranks r;
#ifdef JAM_HAVE_MPI
  if (launched_by_mpi()) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
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

void barrier() {
#ifdef JAM_HAVE_MPI
  if (mpi_active) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

}  // namespace jam
