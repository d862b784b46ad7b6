#pragma once
// Small builders shared by the test suites.
#include <cstdint>
#include <vector>

#include "sim/dynamics/system.hpp"
#include "sim/initial_state.hpp"

namespace jam::test {

/// A system from physical positions (relative to the box centre) in a box of side L.
template <int D, class Contact = HarmonicContact>
System<D, Contact> make_system(const std::vector<std::array<double, D>>& r,
                               const std::vector<int>& type, double box_length, double rate = 0.0,
                               double skin = 0.3, double diameter_ratio = 1.4) {
  ParticleData<D> p;
  p.resize(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    for (int d = 0; d < D; ++d) p.s[d][i] = wrap_unit(r[i][d] / box_length + 0.5);
    p.type[i] = static_cast<std::uint8_t>(type[i]);
    p.id[i] = static_cast<std::uint32_t>(i + 1);
  }
  Species<D> species(diameter_ratio);
  CompressingBox<D> box{box_length, rate, total_particle_volume(p, species)};
  return System<D, Contact>(std::move(p), species, box, skin);
}

/// A random 50:50 system at packing phi.
template <int D, class Contact = HarmonicContact>
System<D, Contact> random_system(std::size_t n, double phi, std::uint64_t seed, double rate = 0.0,
                                 double skin = 0.3) {
  ParticleData<D> p = random_configuration<D>(n, seed);
  Species<D> species;
  const double volume = total_particle_volume(p, species);
  CompressingBox<D> box{CompressingBox<D>::length_for_packing(volume, phi), rate, volume};
  return System<D, Contact>(std::move(p), species, box, skin);
}

/// Separation r_i - r_j (physical, minimum image) at box length L.
template <int D, class Contact>
std::array<double, D> separation(const System<D, Contact>& sys, std::size_t i, std::size_t j,
                                 double L) {
  std::array<double, D> dr;
  pair_separation(sys.particles, i, j, L, dr);
  return dr;
}

}  // namespace jam::test
