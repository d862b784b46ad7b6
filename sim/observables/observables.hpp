#pragma once
// Observables of one configuration, computed only at output points:
//   stress tensor  sigma = L^{-D} sum_{i<j} f_ij^el (x) (r_i - r_j)   (paper, "Model"; its
//                  diagonal only unless asked for: runs write the tensor only with --stress)
//   pressure       p = tr(sigma) / D
//   contacts per particle Z = 2 N_contacts / N, over all particles (rattlers not removed)
//   elastic energy per particle
// with the system's contact law (sim/model/contact_law.hpp) and its one contact test.
//   optionally Z with rattlers removed (sim/observables/rattlers.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "sim/dynamics/system.hpp"
#include "sim/observables/pair_measure.hpp"
#include "sim/observables/rattlers.hpp"

namespace jam {

template <int D>
struct Observables {
  double time = 0.0;
  double packing_fraction = 0.0;
  double pressure = 0.0;
  double contacts_per_particle = 0.0;
  double energy_per_particle = 0.0;
  std::array<std::array<double, D>, D> stress{};
  double contacts_per_particle_no_rattlers = 0.0;  // only when requested
  double rattler_fraction = 0.0;                   // only when requested
};

/// Running sums over the contacts measured so far.
template <int D>
struct ContactSums {
  std::array<std::array<double, D>, D> stress{};
  double energy = 0.0;
  std::size_t contacts = 0;
};

/// Adds one block's contacts to the sums, pair by pair in the list's order: the stress's
/// diagonal only (all the pressure needs; the off-diagonal entries stay 0) unless FullStress.
/// The sums are a local copy, so that they stay in registers across the block.
template <bool FullStress, int D>
ContactSums<D> sum_contacts(ContactSums<D> sums, const MeasureBlock<D>& block, std::uint32_t k0,
                            std::uint32_t k1, const std::uint32_t* row_of_pair,
                            const std::uint32_t* neighbors,
                            std::vector<std::pair<std::uint32_t, std::uint32_t>>* contact_pairs) {
  for (std::uint32_t k = k0; k < k1; ++k) {
    const double c = block.force_over_r[k - k0];
    if (!(c > 0.0)) continue;  // in contact exactly where the force loop gives a force
    ++sums.contacts;
    sums.energy += block.energy[k - k0];
    for (int a = 0; a < D; ++a) {
      if constexpr (FullStress) {
        for (int b = 0; b < D; ++b)
          sums.stress[a][b] += c * block.dr[a][k - k0] * block.dr[b][k - k0];
      } else {
        sums.stress[a][a] += c * block.dr[a][k - k0] * block.dr[a][k - k0];
      }
    }
    if (contact_pairs) contact_pairs->emplace_back(row_of_pair[k], neighbors[k]);
  }
  return sums;
}

/// Measures the configuration at time t. The neighbor list is brought up to date first. The
/// stress tensor's off-diagonal entries only with full_stress (the pressure and the diagonal
/// have the same bits either way).
template <int D, class Contact>
Observables<D> measure(System<D, Contact>& sys, double t, bool remove_rattlers,
                       bool full_stress = true) {
  const double box_length = sys.box.length(t);
  sys.update_neighbors(box_length);
  const std::size_t n = sys.size();
  const PairLoopInput<D, Contact> in = sys.pair_loop_input(box_length);
  const std::uint32_t pairs = sys.neighbors.offsets()[n];

  Observables<D> obs;
  obs.time = t;
  obs.packing_fraction = sys.box.packing_fraction(t);
  ContactSums<D> sums;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> contact_pairs;
  auto* pairs_out = remove_rattlers ? &contact_pairs : nullptr;
  // Pair by pair in the list's order (rows i ascending, j ascending within a row), the
  // separations, f/r and energies from the blocked first pass (pair_measure.hpp: the same
  // bits).
  MeasureBlock<D> block;
  for (std::uint32_t k0 = 0; k0 < pairs; k0 += kMeasureBlockPairs) {
    const std::uint32_t k1 = std::min(pairs, k0 + kMeasureBlockPairs);
    measure_pairs(in, k0, k1, block);
    sums = full_stress
               ? sum_contacts<true>(sums, block, k0, k1, in.row_of_pair, in.neighbors, pairs_out)
               : sum_contacts<false>(sums, block, k0, k1, in.row_of_pair, in.neighbors, pairs_out);
  }
  obs.stress = sums.stress;
  const double volume = std::pow(box_length, D);
  double trace = 0.0;
  for (int a = 0; a < D; ++a) {
    for (int b = 0; b < D; ++b) obs.stress[a][b] /= volume;
    trace += obs.stress[a][a];
  }
  obs.pressure = trace / D;
  obs.contacts_per_particle = 2.0 * static_cast<double>(sums.contacts) / static_cast<double>(n);
  obs.energy_per_particle = sums.energy / static_cast<double>(n);
  if (remove_rattlers) {
    const RattlerAnalysis r = find_rattlers(n, contact_pairs, D + 1);
    obs.contacts_per_particle_no_rattlers = r.contacts_per_particle;
    obs.rattler_fraction = static_cast<double>(r.rattlers) / static_cast<double>(n);
  }
  return obs;
}

}  // namespace jam
