#pragma once
// Chained starts (the supplement's protocol, validated there by Fig. SM-1b): a slower run of a
// sample starts from the configuration the next faster run of the same sample passed through
// at a packing phi'_init, instead of compressing from phi_init again. The faster run writes it
// (--write-start, --write-start-at), the slower one reads it (--read-start). The file is sealed
// like a checkpoint (sealed_file.hpp) and carries the identity of what it holds: the
// fingerprint of the run it was taken from and the packing asked for. A run starts only from
// the identity it expects, which is part of its own fingerprint.
#include <cstdint>
#include <string>

#include "sim/model/particles.hpp"

namespace jam {

template <int D>
struct ChainStart {
  ParticleData<D> particles;
  double box_length = 0.0;
  double packing_fraction = 0.0;  // reached: the first output point at or after the one asked
  std::string identity;
};

/// The identity of the start that the run with fingerprint `parent` leaves at `packing`.
std::string chain_start_identity(const std::string& parent_fingerprint, double packing);

/// A short stable name of an identity (FNV-1a 64, hex): the word fingerprints carry.
std::string chain_start_key(const std::string& identity);

template <int D>
void write_chain_start(const std::string& path, const ChainStart<D>& start);

/// The start at `path`. Throws CorruptCheckpoint (checkpoint.hpp) when it is missing, fails its
/// seal or cannot be read, ForeignCheckpoint when its identity is not `identity` ("" accepts
/// any).
template <int D>
ChainStart<D> read_chain_start(const std::string& path, const std::string& identity);

/// "" when `path` holds a sound start of `identity`; otherwise why not (for planning).
std::string chain_start_problem(const std::string& path, const std::string& identity);

/// The identity stored in the sound start at `path` (throws like read_chain_start).
std::string stored_chain_start_identity(const std::string& path);

}  // namespace jam
