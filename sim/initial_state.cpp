#include "sim/initial_state.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "sim/neighbor/cell_list.hpp"

namespace jam {

template <int D>
ParticleData<D> random_configuration(std::size_t n, std::uint64_t seed) {
  ParticleData<D> p;
  p.resize(n);
  std::mt19937_64 engine(seed);
  for (std::size_t i = 0; i < n; ++i) {
    p.type[i] = static_cast<std::uint8_t>(i < n / 2 ? kSmall : kBig);
    p.id[i] = static_cast<std::uint32_t>(i + 1);
    for (int d = 0; d < D; ++d) p.s[d][i] = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  }
  return p;
}

template <int D>
void sort_spatially(ParticleData<D>& p, const Species<D>& species, double box_length) {
  const int m = std::max(1, static_cast<int>(box_length / species.max_contact_distance));
  CellList<D> cells;
  cells.build(p, m);
  const auto& order = cells.members();
  ParticleData<D> sorted;
  sorted.resize(p.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    for (int d = 0; d < D; ++d) sorted.s[d][k] = p.s[d][i];
    sorted.type[k] = p.type[i];
    sorted.id[k] = p.id[i];
  }
  p = std::move(sorted);
}

template ParticleData<2> random_configuration<2>(std::size_t, std::uint64_t);
template ParticleData<3> random_configuration<3>(std::size_t, std::uint64_t);
template void sort_spatially<2>(ParticleData<2>&, const Species<2>&, double);
template void sort_spatially<3>(ParticleData<3>&, const Species<3>&, double);

}  // namespace jam
