#pragma once
// The times of a compression's output points. The grid is in packing fraction (multiples of
// phi_step), and phi grows as phi(t) = phi_init exp(D rate t) (compressing_box.hpp), so the
// times follow from the box.
#include <cmath>
#include <vector>

#include "sim/model/compressing_box.hpp"

namespace jam {

/// Each packing k phi_step strictly between phi_init and phi_stop, then phi_stop (the point at
/// t = 0 is recorded when the compression begins). Only the last is where a run with dense
/// output lands a step: the configuration written at any other point (a chained start) is the
/// continuous extension's, so that writing it changes nothing in the run.
template <int D>
std::vector<double> output_times(const CompressingBox<D>& box, double phi_init, double phi_stop,
                                 double phi_step) {
  std::vector<double> t;
  for (auto k = static_cast<long long>(std::floor(phi_init / phi_step)) + 1;; ++k) {
    const double phi = static_cast<double>(k) * phi_step;
    if (phi >= phi_stop * (1.0 - 1e-12)) break;
    if (phi > phi_init * (1.0 + 1e-12)) t.push_back(box.time_at_packing(phi));
  }
  t.push_back(box.time_at_packing(phi_stop));
  return t;
}

}  // namespace jam
