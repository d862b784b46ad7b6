#include "campaign/throughput.hpp"

#include "campaign/campaign_dir.hpp"

#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/initial_state.hpp"

namespace jam {
namespace {

template <int D>
double measure(double phi) {
  const std::size_t n = 4096;
  ParticleData<D> p = random_configuration<D>(n, 1);
  const Species<D> species;
  const double volume = total_particle_volume(p, species);
  const double length = CompressingBox<D>::length_for_packing(volume, phi);
  sort_spatially(p, species, length);
  System<D> sys(std::move(p), species, CompressingBox<D>{length, 1e-4, volume}, 0.3);
  OverdampedEuler<D> stepper(n);
  // Warm up (removes the worst overlaps of the random start), then time on this thread's CPU
  // clock: the runs record the same clock (campaign_dir.hpp), so that plan and measured cost
  // agree however loaded the machine is while either is taken.
  for (int k = 0; k < 200; ++k) stepper.step(sys, k * 0.01, 0.01);
  const double start = thread_cpu_seconds();
  std::size_t steps = 0;
  while (thread_cpu_seconds() - start < 0.3) {
    for (int k = 0; k < 20; ++k, ++steps) stepper.step(sys, (200 + steps) * 0.01, 0.01);
  }
  const double seconds = thread_cpu_seconds() - start;
  return static_cast<double>(steps * n) / seconds;
}

}  // namespace

double measure_throughput(int dim) {
  return dim == 2 ? measure<2>(0.84) : measure<3>(0.64);
}

}  // namespace jam
