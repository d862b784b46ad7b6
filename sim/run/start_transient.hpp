#pragma once
// When the start's transient is over. A start that was not relaxed (--relax 0, a LAMMPS data
// file, a chained start from a faster rate) first relaxes while the compression begins: its
// elastic energy falls, fast and with large displacements, before the compression drives the
// system. Integrated at the compression's tolerance (1e-2 at rate 1e-4), the transient leaves
// its error in everything after it (1.3% in the pressure at phi 0.84 from an unrelaxed start;
// docs/performance.md, starts); the run integrates it at the transient tolerance instead
// (sim_config.hpp) until this says it is over. The decision reads only the recorded output
// points, so a resumed run takes it at the same point, and a relaxed start (energy at or below
// the relaxation target) is past it at t = 0.
#include <cstddef>
#include <vector>

#include "sim/observables/observables.hpp"

namespace jam {

/// Over once some recorded point has an energy per particle at or below `settled` (the
/// relaxation target), or one after the first has an energy no lower than the point before it
/// (the compression, not the start's relaxation, sets the energy from there on).
template <int D>
bool start_transient_over(const std::vector<Observables<D>>& points, double settled) {
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (points[k].energy_per_particle <= settled) return true;
    if (k > 0 && points[k].energy_per_particle >= points[k - 1].energy_per_particle) return true;
  }
  return false;
}

}  // namespace jam
