#include "bench/accuracy.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "bench/accuracy_runs.hpp"
#include "bench/lammps_bench.hpp"
#include "bench/process_runs.hpp"
#include "bench/report_files.hpp"
#include "sim/dynamics/integrator_list.hpp"
#include "sim/io/process.hpp"
#include "sim/model/paper_values.hpp"
#include "sim/run/sim_config.hpp"

namespace jam::bench {
namespace fs = std::filesystem;

std::array<double, 3> accuracy_packings(int dim) {
  // The paper's phi_J on the campaigns' output grid (3D: 0.6464 -> 0.6465), so that the whole
  // processes' output points fall on the three packings.
  const double j = std::round(paper_values(dim).phi_j / kCampaignPhiStep) * kCampaignPhiStep;
  return {j - 0.01, j, j + 0.015};
}

namespace {

/// Runs the tasks on `jobs` threads; the first exception is rethrown after all stopped.
void run_pool(std::vector<std::function<void()>>& tasks, int jobs) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex m;
  auto worker = [&] {
    for (std::size_t k; (k = next++) < tasks.size();) {
      try {
        tasks[k]();
      } catch (...) {
        std::lock_guard lock(m);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

// The defaults of `jam sim` (its quality factor writes the data files' masses, which overdamped
// runs ignore).
const SimConfig kDefaults;

std::string process_data(int dim, int seed, const std::string& start) {
  return fmt::format("process_{}_{}d_s{}.data", start, dim, seed);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}

/// A whole process run `repeats` times: its numbers from the first run (the same every time:
/// deterministic), its wall times (loop and process) the medians over the runs.
template <class Run>
RunResult repeated_process(int repeats, Run run) {
  RunResult first = run();
  std::vector<double> wall{first.wall}, process_wall{first.process_wall};
  for (int k = 1; k < repeats; ++k) {
    const RunResult again = run();
    wall.push_back(again.wall);
    process_wall.push_back(again.process_wall);
  }
  first.wall = median(wall);
  first.process_wall = median(process_wall);
  return first;
}

void validate(const AccuracyOptions& o) {
  if (o.n < 64 || o.n % 2) throw std::runtime_error(fmt::format("--n {}: even, >= 64", o.n));
  if (o.seeds < 1) throw std::runtime_error(fmt::format("--seeds {}: at least 1", o.seeds));
  if (o.process_repeats < 1) {
    throw std::runtime_error(fmt::format("--process-repeats {}: at least 1", o.process_repeats));
  }
  if (o.jobs < 1) throw std::runtime_error(fmt::format("--jobs {}: at least 1", o.jobs));
  for (int d : {2, 3}) {
    const double phi = o.start_packing(d);
    if (!(phi > 0 && phi < accuracy_packings(d)[0]))
      throw std::runtime_error(fmt::format("--phi-start-{}d {:g}: must be in (0, {:g})", d, phi,
                                           accuracy_packings(d)[0]));
  }
  if (!(o.relax_time >= 0))
    throw std::runtime_error(fmt::format("--relax-time {:g}: must be >= 0", o.relax_time));
  if (!(o.reference_dt > 0))
    throw std::runtime_error(fmt::format("--reference-dt {:g}: must be positive", o.reference_dt));
  for (double r : o.rates)
    if (!(r > 0)) throw std::runtime_error(fmt::format("--rates {:g}: must be positive", r));
  for (const auto* list : {&o.euler_dt, &o.heun_dt})
    for (double dt : *list)
      if (!(dt > 0)) throw std::runtime_error(fmt::format("time step {:g}: must be positive", dt));
  for (double quality_factor : o.verlet_quality_factors)
    if (!(quality_factor > 0))
      throw std::runtime_error(fmt::format("--verlet-q {:g}: must be positive", quality_factor));
  for (double tol : o.chebyshev_tolerance)
    if (!(tol > 0 && std::isfinite(tol)))
      throw std::runtime_error(fmt::format("--chebyshev-tolerance {:g}: must be positive", tol));
  for (const auto* list : {&o.verlet_fraction, &o.lammps_fraction})
    for (double f : *list)
      if (!(f > 0 && f < 1))
        throw std::runtime_error(fmt::format("dt fraction {:g}: must be in (0, 1)", f));
}

void analyse(AccuracyResult& res) {
  // Reference per (dim, rate) and seed: Richardson from the two finest Heun runs.
  std::map<std::tuple<int, double, std::string>, std::vector<std::array<double, 3>>> p_ref;
  for (auto& ref : res.references) {
    const Method* h[3] = {nullptr, nullptr, nullptr};
    for (const auto& m : res.methods) {
      if (m.dim != ref.dim || m.rate != ref.rate || m.start != ref.start || !m.is_reference)
        continue;
      const int level = m.integrator == "reference-h" ? 0 : m.integrator == "reference-h/2" ? 1 : 2;
      h[level] = &m;
    }
    const std::size_t seeds = h[2]->pressure.size();
    auto& pr = p_ref[{ref.dim, ref.rate, ref.start}];
    pr.resize(seeds);
    for (int k = 0; k < 3; ++k) {
      double d01 = 0, d12 = 0, rem = 0, mean = 0;
      for (std::size_t s = 0; s < seeds; ++s) {
        const double p0 = h[0]->pressure[s][k], p1 = h[1]->pressure[s][k],
                     p2 = h[2]->pressure[s][k];
        pr[s][k] = p2 + (p2 - p1) / 3.0;
        d01 += std::abs(p0 - p1);
        d12 += std::abs(p1 - p2);
        rem += std::abs(pr[s][k] - p2) / pr[s][k];
        mean += pr[s][k];
      }
      ref.p[k] = mean / seeds;
      ref.ratio[k] = d12 > 0 ? d01 / d12 : std::numeric_limits<double>::infinity();
      ref.remaining[k] = rem / seeds;
    }
  }
  for (auto& m : res.methods) {
    m.wall_median = median(m.wall);
    if (!m.process_wall.empty()) m.process_wall_median = median(m.process_wall);
    const auto& pr = p_ref[{m.dim, m.rate, m.start}];
    const std::size_t seeds = m.pressure.size();
    m.max_error = 0;
    for (int k = 0; k < 3; ++k) {
      double mean = 0, ss = 0;
      for (std::size_t s = 0; s < seeds; ++s) mean += (m.pressure[s][k] / pr[s][k] - 1) / seeds;
      for (std::size_t s = 0; s < seeds; ++s) {
        const double e = m.pressure[s][k] / pr[s][k] - 1 - mean;
        ss += e * e;
      }
      m.error[k] = std::abs(mean);
      m.error_se[k] = seeds > 1 ? std::sqrt(ss / (seeds - 1) / seeds) : 0.0;
      if (m.error[k] >= m.max_error) {
        m.max_error = m.error[k];
        m.max_error_se = m.error_se[k];
      }
    }
  }
}

}  // namespace

AccuracyResult run_accuracy(const AccuracyOptions& o) {
  validate(o);
  for (int d : o.dims) require_on_grid(accuracy_packings(d));
  const bool lammps = o.lammps && lmp_available();
  if (o.lammps && !lammps) fmt::print(stderr, "jam bench: no lmp on the PATH, jam only\n");
  const fs::path work = make_temp_directory("jam-bench-accuracy");

  // Relaxed starts, one per (dimension, seed), shared by every rate and method.
  std::map<std::pair<int, int>, Start> starts;
  {
    std::vector<std::function<void()>> tasks;
    std::mutex m;
    for (int d : o.dims)
      for (int s = 0; s < o.seeds; ++s)
        tasks.push_back([&, d, s] {
          Start st = relaxed_start(d, o.n, static_cast<std::uint64_t>(1000 + s), o.start_packing(d),
                                   o.relax_time);
          fmt::print(stderr, "  {}D start {}: energy per particle {:.2g}\n", d, s,
                     st.energy_per_particle);
          std::lock_guard lock(m);
          starts[{d, s}] = std::move(st);
        });
    fmt::print(stderr, "jam bench accuracy: relaxing {} starts\n", tasks.size());
    run_pool(tasks, o.jobs);
  }
  std::map<std::pair<int, int>, Start> unrelaxed;
  if (o.unrelaxed)
    for (int d : o.dims)
      for (int s = 0; s < o.seeds; ++s)
        unrelaxed[{d, s}] =
            unrelaxed_start(d, o.n, static_cast<std::uint64_t>(1000 + s), o.start_packing(d));
  auto start_of = [&](const Method& m, int s) -> const Start& {
    return m.start == "unrelaxed" ? unrelaxed.at({m.dim, s}) : starts.at({m.dim, s});
  };

  AccuracyResult res;
  for (int d : o.dims) {
    const double bound_unit = 4.0 / d;  // stability bound of Verlet: 4 Q^2 / D
    for (double rate : o.rates) {
      res.references.push_back({d, rate, "relaxed", accuracy_packings(d), {}, {}, {}});
      auto add = [&](const std::string& engine, const std::string& integrator,
                     double quality_factor, double dt, bool reference,
                     const std::string& start = "relaxed") {
        Method m;
        m.dim = d;
        m.rate = rate;
        m.engine = engine;
        m.integrator = integrator;
        m.quality_factor = quality_factor;
        m.dt = dt;
        m.is_reference = reference;
        m.start = start;
        m.wall.resize(o.seeds);
        m.pressure.resize(o.seeds);
        res.methods.push_back(m);
      };
      auto add_references = [&](const std::string& start) {
        add("jam", "reference-h", 0, o.reference_dt, true, start);
        add("jam", "reference-h/2", 0, o.reference_dt / 2, true, start);
        add("jam", "reference-h/4", 0, o.reference_dt / 4, true, start);
      };
      add_references("relaxed");
      // The headline: `jam sim` processes at its defaults, and with the output points landed
      // on (as before dense output); from unrelaxed starts also without the transient
      // tolerance, the error it removes.
      auto add_process = [&](const std::string& name, std::vector<std::string> args,
                             const std::string& start) {
        add("jam-process", name, 0, kDefaults.dt, false, start);
        res.methods.back().args = std::move(args);
        res.methods.back().tolerance = auto_tolerance(rate);  // its cost estimate
        res.methods.back().process_wall.resize(o.seeds);
      };
      add_process("defaults", {}, "relaxed");
      add_process("landed", {"--dense-output", "0"}, "relaxed");
      if (o.unrelaxed) {
        res.references.push_back({d, rate, "unrelaxed", accuracy_packings(d), {}, {}, {}});
        add_references("unrelaxed");
        add_process("defaults", {}, "unrelaxed");
        add_process("landed", {"--dense-output", "0"}, "unrelaxed");
        add_process("no transient tolerance", {"--transient-tolerance", "off"}, "unrelaxed");
      }
      for (double dt : o.euler_dt) add("jam", "euler", 0, dt, false);
      for (double dt : o.heun_dt) add("jam", "heun", 0, dt, false);
      for (double tol : o.chebyshev_tolerance) {
        add("jam", "chebyshev", 0, 0.1, false);
        res.methods.back().tolerance = tol;
      }
      for (double quality_factor : o.verlet_quality_factors) {
        for (double f : o.verlet_fraction)
          add("jam", "verlet", quality_factor, f * bound_unit * quality_factor * quality_factor,
              false);
        if (lammps)
          for (double f : o.lammps_fraction) {
            add("lammps", "verlet", quality_factor,
                f * bound_unit * quality_factor * quality_factor, false);
            res.methods.back().process_wall.resize(o.seeds);
            add("lammps-shifted", "verlet", quality_factor,
                f * bound_unit * quality_factor * quality_factor, false);  // same runs
            res.methods.back().process_wall.resize(o.seeds);
          }
      }
    }
  }
  // LAMMPS data files: one per (dimension, seed, Q).
  if (lammps) {
    for (const auto& [key, start] : starts)
      for (double quality_factor : o.verlet_quality_factors)
        write_start(
            start, quality_factor,
            (work / fmt::format("start_{}d_s{}_q{:g}.data", key.first, key.second, quality_factor))
                .string());
  }
  // ... and one per (start, dimension, seed) for the jam processes.
  for (const auto& [key, start] : starts)
    write_start(start, kDefaults.quality_factor,
                (work / process_data(key.first, key.second, "relaxed")).string());
  for (const auto& [key, start] : unrelaxed)
    write_start(start, kDefaults.quality_factor,
                (work / process_data(key.first, key.second, "unrelaxed")).string());
  // Every (method, seed) is a task; longest first so that the pool ends together.
  std::vector<std::function<void()>> tasks;
  std::vector<double> cost;
  std::atomic<int> done{0};
  int total = 0;
  for (std::size_t mi = 0; mi < res.methods.size(); ++mi) {
    if (res.methods[mi].engine == "lammps-shifted") continue;  // filled by the run before
    for (int s = 0; s < o.seeds; ++s) {
      Method& m = res.methods[mi];
      const double t_end =
          std::log(accuracy_packings(m.dim)[2] / o.start_packing(m.dim)) / (m.dim * m.rate);
      const std::string costed = m.engine == "jam-process" ? "chebyshev" : m.integrator;
      cost.push_back(t_end *
                     force_evaluations_per_time(costed, m.dim, m.dt, m.rate, m.tolerance, false,
                                                static_cast<double>(o.n)) *
                     (m.engine == "lammps" ? 3 : 1) * (m.dim == 3 ? 2 : 1));
      tasks.push_back([&, mi, s] {
        Method& m = res.methods[mi];
        const auto phi = accuracy_packings(m.dim);
        RunResult r;
        if (m.engine == "jam-process") {
          r = repeated_process(o.process_repeats, [&] {
            return run_jam_process(work, m.dim, process_data(m.dim, s, m.start),
                                   fmt::format("m{}_s{}.h5", mi, s), m.rate, m.args, phi);
          });
          m.process_wall[s] = r.wall;
        } else if (m.engine == "lammps") {
          r = repeated_process(o.process_repeats, [&] {
            return run_lammps_compression(
                work, o.reference_dir,
                fmt::format("start_{}d_s{}_q{:g}.data", m.dim, s, m.quality_factor),
                fmt::format("m{}_s{}.log", mi, s), m.dim, m.rate, m.dt, o.start_packing(m.dim),
                phi);
          });
        } else {
          const std::string integrator = m.is_reference ? std::string("heun") : m.integrator;
          r = run_jam(start_of(m, s), m.rate, integrator, m.quality_factor, m.tolerance, m.dt, phi);
        }
        m.wall[s] = r.wall;
        m.pressure[s] = r.pressure;
        if (m.engine == "lammps") {
          m.process_wall[s] = res.methods[mi + 1].process_wall[s] = r.process_wall;
          res.methods[mi + 1].wall[s] = r.wall;
          res.methods[mi + 1].pressure[s] = r.pressure_shifted;
        }
        fmt::print(stderr, "  [{}/{}] {}D rate {:g} {} {} {} q {:g} dt {:g} seed {}: {:.2f} s\n",
                   ++done, total, m.dim, m.rate, m.start, m.engine, m.integrator, m.quality_factor,
                   m.dt, s, r.wall);
      });
    }
  }
  total = static_cast<int>(tasks.size());
  std::vector<std::size_t> order(tasks.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
  std::vector<std::function<void()>> sorted;
  for (auto k : order) sorted.push_back(std::move(tasks[k]));
  try {
    run_pool(sorted, o.jobs);
  } catch (const std::exception& e) {
    // The logs the error names stay for reading.
    throw std::runtime_error(fmt::format("{} (work directory {} kept)", e.what(), work.string()));
  }
  fs::remove_all(work);
  analyse(res);
  return res;
}

}  // namespace jam::bench
