#pragma once
// A checksum of everything an HDF5 file holds: every attribute (name, kind, value) and every
// dataset (name, shape, values) of every group, in name order, except the attributes named in
// `skip` (the checksum's own attribute). Run files and stats.h5 store it in their attribute
// "checksum", so that a flipped bit anywhere, in a table of stats.h5 as much as in a run file's
// compression_rate, is caught before the file is trusted. (Checkpoints, relaxed and chained
// starts are sealed whole in their HDF5 user block instead: sealed_file.hpp.)
//
// FNV-1a, 64 bit: a guard against damage (bit rot, a torn copy, a hand edit), not against
// someone who forges files on purpose; it changes with any single flipped bit.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/io/hdf5_file.hpp"

namespace jam {

std::uint64_t content_checksum(const h5::File& f, const std::vector<std::string>& skip);

/// The same hash of a run of bytes (a digest of a list of names and checksums: stats.h5's
/// inputs_checksum, stats/stats_inputs.hpp).
std::uint64_t bytes_checksum(const std::string& bytes);

/// The checksum as stored: 16 lowercase hex digits.
std::string checksum_text(std::uint64_t h);

/// Computes the checksum of f (skipping "checksum") and stores it as attribute "checksum".
void seal(h5::File& f);

/// "" when f holds an attribute "checksum" that matches its content; otherwise why not
/// ("no checksum" for files written before checksums, or the mismatch).
std::string seal_problem(const h5::File& f);

}  // namespace jam
