#pragma once
// Initial configurations: uniformly random positions, N/2 small and N/2 big.
//
// Generator (deterministic on every platform): std::mt19937_64 seeded with the seed, whose
// output sequence the C++ standard fixes; each coordinate is (x >> 11) * 2^-53, a uniform
// double in [0, 1). Particles 0..N/2-1 are small, the rest big; coordinates are drawn
// particle by particle, x then y (then z). The particles are then ordered along the cell
// grid for memory locality and numbered 1..N in that order (the LAMMPS atom ids).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/model/compressing_box.hpp"
#include "sim/model/particles.hpp"
#include "sim/model/species.hpp"

namespace jam {

template <int D>
ParticleData<D> random_configuration(std::size_t n, std::uint64_t seed);

/// Reorders particles cell by cell (cells of roughly one big diameter at box length L),
/// keeping their ids. Improves cache locality of the force loop for large N.
template <int D>
void sort_spatially(ParticleData<D>& p, const Species<D>& species, double box_length);

/// Sum of particle volumes.
template <int D>
double total_particle_volume(const ParticleData<D>& p, const Species<D>& species) {
  double v = 0.0;
  for (auto t : p.type) v += species.volume[t];
  return v;
}

/// A random start at packing phi: random_configuration, the box length that gives phi, the
/// particles sorted cell by cell and numbered 1..N in that order (the LAMMPS atom ids).
template <int D>
struct RandomStart {
  ParticleData<D> particles;
  double box_length = 0.0;
  double particle_volume = 0.0;
};

template <int D>
RandomStart<D> random_start(std::size_t n, std::uint64_t seed, const Species<D>& species,
                            double phi) {
  RandomStart<D> r;
  r.particles = random_configuration<D>(n, seed);
  r.particle_volume = total_particle_volume(r.particles, species);
  r.box_length = CompressingBox<D>::length_for_packing(r.particle_volume, phi);
  sort_spatially(r.particles, species, r.box_length);
  for (std::size_t i = 0; i < r.particles.size(); ++i)
    r.particles.id[i] = static_cast<std::uint32_t>(i + 1);
  return r;
}

}  // namespace jam
