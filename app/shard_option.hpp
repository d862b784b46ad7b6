#pragma once
// `jam campaign run --shard K/N` or `--shard auto` (this Slurm array task's share).
#include <string>
#include <utility>

namespace jam {

/// {K, N} (K from 1). `auto`: K = (ID - MIN) / STEP + 1 of N = COUNT from the Slurm array
/// variables, so that arrays numbered from 0 or 1, or with a step, all work. Throws
/// CLI::ValidationError naming --shard and the value.
std::pair<int, int> parse_shard(const std::string& shard);

}  // namespace jam
