#pragma once
// CPU seconds of the calling thread: a run's cost in core-seconds, which other work on a
// shared machine (or a campaign stopped with SIGSTOP) does not inflate as it does the wall.
#include <time.h>

namespace jam {

inline double thread_cpu_seconds() {
  timespec t{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) != 0) return 0.0;
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace jam
