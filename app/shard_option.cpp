#include "app/shard_option.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace jam {
namespace {

/// A whole number from the environment variable `name` (`fallback` when unset).
long slurm_number(const char* name, long fallback) {
  const char* text = std::getenv(name);
  if (!text) {
    if (fallback >= 0) return fallback;
    throw CLI::ValidationError("--shard",
                               fmt::format("auto: {} is not set (not a Slurm array task)", name));
  }
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 0) {
    throw CLI::ValidationError("--shard",
                               fmt::format("auto: {}={} is not a whole number", name, text));
  }
  return v;
}

}  // namespace

std::pair<int, int> parse_shard(const std::string& shard) {
  if (shard == "auto") {
    const long id = slurm_number("SLURM_ARRAY_TASK_ID", -1);
    const long count = slurm_number("SLURM_ARRAY_TASK_COUNT", -1);
    const long first = slurm_number("SLURM_ARRAY_TASK_MIN", -1);
    const long step = std::max(1L, slurm_number("SLURM_ARRAY_TASK_STEP", 1));
    const long k = (id - first) / step + 1;
    if (id < first || (id - first) % step != 0 || count < 1 || k > count || count > 1000000) {
      throw CLI::ValidationError(
          "--shard", fmt::format("auto: task {} of an array of {} from {} in steps of {} is not "
                                 "one of its tasks",
                                 id, count, first, step));
    }
    return {static_cast<int>(k), static_cast<int>(count)};
  }
  int k = 0, n = 0;
  char rest = 0;
  if (std::sscanf(shard.c_str(), "%d/%d%c", &k, &n, &rest) != 2 || n < 1 || k < 1 || k > n) {
    throw CLI::ValidationError(
        "--shard", shard +
                       ": must read K/N with 1 <= K <= N, e.g. 3/8 (K counts from 1; for a "
                       "Slurm array numbered from 0, give --shard auto)");
  }
  return {k, n};
}

}  // namespace jam
