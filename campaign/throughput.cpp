#include "campaign/throughput.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "campaign/campaign_dir.hpp"
#include "sim/dynamics/integrator_list.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/initial_state.hpp"

namespace jam {
namespace {

constexpr std::int64_t kLargestProbe = 65536;

template <int D>
double measure(double phi, std::size_t n) {
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

double measure_throughput(int dim, std::int64_t n) {
  const auto size = static_cast<std::size_t>(std::clamp<std::int64_t>(n, 2, kLargestProbe));
  return dim == 2 ? measure<2>(0.84, size) : measure<3>(0.64, size);
}

double Throughput::at(std::int64_t n) const {
  if (per_size.empty()) throw std::logic_error("Throughput: no size probed");
  auto above = per_size.lower_bound(n);
  if (above == per_size.end()) return std::prev(above)->second;
  if (above == per_size.begin() || above->first == n) return above->second;
  const auto below = std::prev(above);
  // Nearest in log N.
  return std::log(static_cast<double>(above->first) / static_cast<double>(n)) <
                 std::log(static_cast<double>(n) / static_cast<double>(below->first))
             ? above->second
             : below->second;
}

double Throughput::core_seconds(std::int64_t n, double particle_steps) const {
  return particle_steps * evaluation_cost / at(n);
}

Throughput measure_throughput(const SimConfig& run, const std::vector<std::int64_t>& sizes) {
  Throughput t;
  for (const std::int64_t n : sizes) t.per_size[n] = measure_throughput(run.dim, n);
  t.evaluation_cost =
      is_adaptive_integrator(run.resolved_integrator()) ? kChebyshevEvaluationCost : 1.0;
  return t;
}

}  // namespace jam
