#include "campaign/throughput.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "campaign/campaign_dir.hpp"
#include "campaign/toml_file.hpp"
#include "sim/dynamics/integrator_list.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/install_paths.hpp"

namespace jam {
namespace {

constexpr std::int64_t kLargestProbe = 65536;
constexpr int kProbeRepeats = 3;  // the probe's repeats when it prices a plan

double evaluation_cost(const SimConfig& run) {
  return is_adaptive_integrator(run.resolved_integrator()) ? kChebyshevEvaluationCost : 1.0;
}

/// The numbers of `key` in [section] of `file`, or an error naming them.
std::vector<double> numbers(const toml::table& t, const char* key, const std::string& file,
                            const std::string& section) {
  const toml::array* a = t[key].as_array();
  if (!a)
    throw std::runtime_error(
        fmt::format("{}: [{}] {}: missing or not an array", file, section, key));
  std::vector<double> out;
  for (const auto& node : *a) {
    const std::optional<double> x = toml_number(&node);
    if (!x) throw std::runtime_error(fmt::format("{}: [{}] {}: not a number", file, section, key));
    out.push_back(*x);
  }
  return out;
}

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
  t.evaluation_cost = evaluation_cost(run);
  return t;
}

ProbeSpread probe_spread(int dim, std::int64_t n, int repeats) {
  std::vector<double> x;
  for (int k = 0; k < std::max(1, repeats); ++k) x.push_back(measure_throughput(dim, n));
  std::sort(x.begin(), x.end());
  const std::size_t m = x.size();
  return {x.front(), m % 2 ? x[m / 2] : 0.5 * (x[m / 2 - 1] + x[m / 2]), x.back(),
          static_cast<int>(m)};
}

std::string stored_throughput_file() {
  return data_path("reference/throughput.toml").string();
}

std::optional<double> stored_throughput(const std::string& file, int dim, std::int64_t n) {
  if (!std::filesystem::exists(file)) return std::nullopt;
  const toml::table t = read_toml_file("throughput measurements", file);
  const std::string key = fmt::format("{}d", dim);
  const toml::table* table = t[key].as_table();
  if (!table) return std::nullopt;
  const std::vector<double> sizes = numbers(*table, "n", file, key),
                            speed = numbers(*table, "particle_steps_per_second", file, key);
  if (sizes.empty() || sizes.size() != speed.size())
    throw std::runtime_error(fmt::format(
        "{}: [{}] n and particle_steps_per_second: {} and {} values (one of each per size)", file,
        key, sizes.size(), speed.size()));
  for (std::size_t k = 0; k < sizes.size(); ++k)
    if (!(sizes[k] >= 2) || !(speed[k] > 0) || !std::isfinite(speed[k]) ||
        (k > 0 && !(sizes[k] > sizes[k - 1])))
      throw std::runtime_error(fmt::format(
          "{}: [{}] n {} with particle_steps_per_second {}: sizes increasing from 2, speeds "
          "positive",
          file, key, sizes[k], speed[k]));
  const double x = std::log(static_cast<double>(n));
  if (x <= std::log(sizes.front())) return speed.front();
  if (x >= std::log(sizes.back())) return speed.back();
  std::size_t k = 1;
  while (std::log(sizes[k]) < x) ++k;
  const double a = std::log(sizes[k - 1]), b = std::log(sizes[k]);
  return speed[k - 1] + (speed[k] - speed[k - 1]) * (x - a) / (b - a);
}

Throughput plan_throughput(const SimConfig& run, const std::vector<std::int64_t>& sizes, bool probe,
                           const std::string& file) {
  Throughput t;
  t.evaluation_cost = evaluation_cost(run);
  for (const std::int64_t n : sizes) {
    const std::optional<double> stored = probe ? std::nullopt : stored_throughput(file, run.dim, n);
    if (stored) {
      t.per_size[n] = *stored;
      t.source[n] =
          "stored, " +
          (file == stored_throughput_file() ? std::string("reference/throughput.toml") : file);
      continue;
    }
    // The probe on this machine now: its spread said, so that a busy machine shows.
    const ProbeSpread p = probe_spread(run.dim, n, kProbeRepeats);
    t.per_size[n] = p.median;
    t.source[n] =
        fmt::format("probe of this machine, {} repeats: min {:.3g}, median {:.3g}, max {:.3g}",
                    p.repeats, p.min, p.median, p.max);
  }
  return t;
}

Throughput with_finished_runs(const Throughput& base, const std::vector<PlannedRun>& plan) {
  struct Measured {
    double particle_steps = 0, seconds = 0;
    int runs = 0;
  };
  std::map<std::int64_t, Measured> by_size;
  for (const PlannedRun& run : plan) {
    const std::optional<RunRecord> r = read_run_record(run);
    // A record without particle-steps (older, or resumed from a checkpoint) prices nothing.
    if (!r || r->status != "done" || !(r->cpu_seconds > 0) || r->particle_steps <= 0) continue;
    Measured& m = by_size[run.n];
    m.particle_steps += static_cast<double>(r->particle_steps);
    m.seconds += r->cpu_seconds;
    ++m.runs;
  }
  Throughput t = base;
  for (const auto& [n, m] : by_size) {
    if (!t.per_size.count(n)) continue;
    // The runs' particle-steps are the integrator's evaluations: in probe steps, times its cost.
    t.per_size[n] = m.particle_steps / m.seconds * t.evaluation_cost;
    t.source[n] = fmt::format("this campaign's {} finished run{}, their recorded CPU seconds",
                              m.runs, m.runs == 1 ? "" : "s");
  }
  return t;
}

}  // namespace jam
