#pragma once
// A whole-file seal for the files jam resumes from (checkpoints, relaxed starts): the first
// 512 bytes of the HDF5 file are its user block, which the HDF5 library leaves alone, and hold
// "jam-seal fnv1a64 <16 hex digits> <bytes>" for every byte after them. The seal is checked
// before the HDF5 library parses anything, so a damaged file (one flipped bit in the positions,
// a truncated copy) is refused whole and never reaches the HDF5 reader.
#include <cstdint>
#include <cstdio>
#include <string>

#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"

namespace jam {

/// User block size of sealed files (HDF5 wants a power of two >= 512).
constexpr std::uint64_t kSealBytes = 512;

/// Writes the seal of the closed HDF5 file at path (created with a kSealBytes user block).
void seal_file(const std::string& path);

/// "" when the file at path carries a seal that matches its bytes; otherwise why not. Anything
/// but a regular file (a FIFO, a device) is refused before it is read, without waiting.
std::string sealed_file_problem(const std::string& path);

/// Writes a sealed HDF5 file at path atomically: fill(h5::File&) writes its content under a
/// temporary name, which is then sealed and renamed to path; on any error it is removed.
template <class Fill>
void write_sealed(const std::string& path, Fill&& fill) {
  const std::string temporary = AtomicFile::temporary_name(path);
  try {
    h5::File f = h5::File::create(temporary, kSealBytes);
    fill(f);
    f.close();
    seal_file(temporary);
    AtomicFile::publish(path);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

}  // namespace jam
