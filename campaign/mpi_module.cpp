// jam-mpi.so: the MpiModule table (mpi_module.hpp) over the MPI library it links.
#include "campaign/mpi_module.hpp"

#include <mpi.h>

namespace {

void start(int* argc, char*** argv, int* rank, int* size, int* thread_multiple) {
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided);
  *thread_multiple = provided >= MPI_THREAD_MULTIPLE ? 1 : 0;
  MPI_Comm_rank(MPI_COMM_WORLD, rank);
  MPI_Comm_size(MPI_COMM_WORLD, size);
}

void stop() {
  MPI_Finalize();
}

void abort_all(int code) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

void broadcast_count(long long* count) {
  MPI_Bcast(count, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
}

void broadcast_values(std::int64_t* values, int count) {
  MPI_Bcast(values, count, MPI_INT64_T, 0, MPI_COMM_WORLD);
}

int reduce(int value, MPI_Op op) {
  int result = value;
  MPI_Allreduce(&value, &result, 1, MPI_INT, op, MPI_COMM_WORLD);
  return result;
}
int max_over_ranks(int value) {
  return reduce(value, MPI_MAX);
}
int sum_over_ranks(int value) {
  return reduce(value, MPI_SUM);
}

void send(std::int64_t value, int destination, int tag) {
  MPI_Send(&value, 1, MPI_INT64_T, destination, tag, MPI_COMM_WORLD);
}

std::int64_t receive(int source, int tag) {
  std::int64_t value = -1;
  MPI_Recv(&value, 1, MPI_INT64_T, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return value;
}

void receive_any(std::int64_t* value, int* source, int* tag) {
  MPI_Status status;
  MPI_Recv(value, 1, MPI_INT64_T, MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
  *source = status.MPI_SOURCE;
  *tag = status.MPI_TAG;
}

void barrier() {
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const jam::MpiModule jam_mpi_module = {
    jam::kMpiModuleAbi, start,          stop, abort_all, broadcast_count, broadcast_values,
    max_over_ranks,     sum_over_ranks, send, receive,   receive_any,     barrier};
