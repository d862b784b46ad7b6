#pragma once
// The particles as datasets of a sealed HDF5 file (checkpoints, relaxed starts, chained
// starts): s_0 ... s_{D-1} (scaled positions), id, type. Reading validates what a run relies
// on: equal lengths, types 0 or 1, positions in [0, 1).
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "sim/io/hdf5_file.hpp"
#include "sim/model/particles.hpp"

namespace jam {

template <int D>
void write_particles(h5::File& f, const ParticleData<D>& particles) {
  for (int d = 0; d < D; ++d) f.write_dataset(fmt::format("s_{}", d), particles.s[d]);
  f.write_dataset("id", particles.id);
  f.write_dataset("type", std::vector<std::uint32_t>(particles.type.begin(), particles.type.end()));
}

/// Throws std::runtime_error naming `path` when the datasets are inconsistent.
template <int D>
ParticleData<D> read_particles(const h5::File& f, const std::string& path) {
  ParticleData<D> p;
  p.id = f.read_dataset_u32("id");
  if (p.id.empty()) throw std::runtime_error(path + ": no particles");
  p.resize(p.id.size());
  // Every other dataset is checked against id's length before it is read.
  const auto type = f.read_dataset_u32("type", h5::exactly(p.size()));
  for (std::size_t i = 0; i < type.size(); ++i) {
    if (type[i] > 1) throw std::runtime_error(path + ": particle type out of range");
    p.type[i] = static_cast<std::uint8_t>(type[i]);
  }
  for (int d = 0; d < D; ++d) {
    p.s[d] = f.read_dataset(fmt::format("s_{}", d), h5::exactly(p.size()));
    for (double x : p.s[d]) {
      if (!(x >= 0.0 && x < 1.0)) throw std::runtime_error(path + ": position outside the box");
    }
  }
  return p;
}

}  // namespace jam
