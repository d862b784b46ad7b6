#include "campaign/ranks.hpp"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "campaign/mpi_module.hpp"
#include "sim/io/install_paths.hpp"

namespace jam {
namespace {
// The loaded module's table (mpi_module.hpp), while MPI runs; null otherwise.
const MpiModule* mpi = nullptr;
bool mpi_multiple = false;

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

#ifdef JAM_MPI_MODULE_BUILD_PATH
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(v)) return true;
  }
  return false;
}

/// jam-mpi.so: installed beside jam (<prefix>/lib/jam/), else where this build made it.
std::filesystem::path mpi_module_path() {
  const std::filesystem::path installed =
      executable_directory().parent_path() / "lib" / "jam" / "jam-mpi.so";
  std::error_code ec;
  if (std::filesystem::exists(installed, ec)) return installed;
  return JAM_MPI_MODULE_BUILD_PATH;
}

/// Loads the module, or exits with status 2 and one line saying why. RTLD_GLOBAL: OpenMPI's
/// own components, which it loads later, look up libmpi's symbols in the global scope.
const MpiModule* load_mpi_module() {
  const std::string path = mpi_module_path().string();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
  const auto* table =
      handle ? static_cast<const MpiModule*>(dlsym(handle, kMpiModuleSymbol)) : nullptr;
  if (!table || table->abi != kMpiModuleAbi) {
    const char* why =
        handle ? (table ? "built by another version of jam" : "not jam's module") : dlerror();
    std::fprintf(stderr,
                 "jam: error: started by an MPI launcher, but its MPI module %s cannot be "
                 "used: %s\n",
                 path.c_str(), why);
    std::exit(2);
  }
  return table;
}
#endif
}  // namespace

bool built_with_mpi() {
#ifdef JAM_MPI_MODULE_BUILD_PATH
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
#ifdef JAM_MPI_MODULE_BUILD_PATH
  if (launched_by_mpi()) {
    // Worker threads ask rank 0 for runs themselves (run_queue.hpp): ask for full thread
    // support, and fall back to a split made in advance when the library does not give it.
    const MpiModule* module = load_mpi_module();
    int multiple = 0;
    module->start(argc, argv, &r.rank, &r.size, &multiple);
    mpi_multiple = multiple != 0;
    mpi = module;
  }
#endif
  return r;
}

void stop_ranks() {
  if (mpi) mpi->stop();
  mpi = nullptr;
}

void abort_ranks(int code) {
  if (mpi) mpi->abort(code);
}

std::vector<std::int64_t> broadcast_from_root(std::vector<std::int64_t> values) {
  if (mpi) {
    long long count = static_cast<long long>(values.size());
    mpi->broadcast_count(&count);
    values.resize(static_cast<std::size_t>(count));
    mpi->broadcast_values(values.data(), static_cast<int>(count));
  }
  return values;
}

int max_over_ranks(int value) {
  return mpi ? mpi->max_over_ranks(value) : value;
}

int sum_over_ranks(int value) {
  return mpi ? mpi->sum_over_ranks(value) : value;
}

bool threads_may_use_mpi() {
  return mpi && mpi_multiple;
}

void send_value(std::int64_t value, int destination, int tag) {
  if (mpi) mpi->send(value, destination, tag);
}

std::int64_t receive_value(int source, int tag) {
  return mpi ? mpi->receive(source, tag) : -1;
}

Message receive_any() {
  Message m;
  if (mpi) mpi->receive_any(&m.value, &m.source, &m.tag);
  return m;
}

void barrier() {
  if (mpi) mpi->barrier();
}

}  // namespace jam
