#include "bench/throughput.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "bench/lammps_bench.hpp"
#include "bench/report_files.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/process.hpp"
#include "sim/parallel.hpp"

namespace jam::bench {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size() / 2;
  return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
}
constexpr double kRate = 1e-4, kDt = 0.01, kLammpsQualityFactor = 0.1;

template <int D>
System<D> near_jamming(std::int64_t n) {
  const double phi = D == 2 ? 0.84 : 0.64;
  const Species<D> species;
  RandomStart<D> r = random_start<D>(static_cast<std::size_t>(n), 1, species, phi);
  System<D> sys(std::move(r.particles), species,
                CompressingBox<D>{r.box_length, 0.0, r.particle_volume}, 0.3);
  OverdampedEuler<D> warm(sys.size());
  for (int k = 0; k < 150; ++k) warm.step(sys, 0.0, 0.05);
  sys.box.compression_rate = kRate;
  return sys;
}

/// Runs `other` on a second thread while `here` runs on this one, and rethrows the first
/// exception once both have finished (one escaping a std::thread would abort the program).
template <class F, class G>
void side_by_side(F&& other, G&& here) {
  std::exception_ptr other_error;
  std::thread thread([&] {
    try {
      other();
    } catch (...) {
      other_error = std::current_exception();
    }
  });
  try {
    here();
  } catch (...) {
    thread.join();
    throw;
  }
  thread.join();
  if (other_error) std::rethrow_exception(other_error);
}

/// Runs `steps` Euler steps; returns the wall time in seconds.
template <int D>
double timed_steps(System<D>& sys, long steps) {
  OverdampedEuler<D> stepper(sys.size());
  const auto start = Clock::now();
  for (long k = 0; k < steps; ++k) stepper.step(sys, static_cast<double>(k) * kDt, kDt);
  return std::chrono::duration<double>(Clock::now() - start).count();
}

template <int D>
void measure_size(const ThroughputOptions& o, std::int64_t n, const fs::path& work,
                  std::vector<ThroughputRow>& rows) {
  System<D> sys = near_jamming<D>(n);
  // About o.seconds at the expected speed, at least 10 steps.
  const double expected = D == 2 ? 4e7 : 2e7;
  const long steps = std::max(10L, std::lround(o.seconds * expected / static_cast<double>(n)));

  ThroughputRow one;
  one.dim = D;
  one.n = n;
  one.mode = "1 core";
  one.steps = steps;
  ThroughputRow campaign = one, single = one;
  campaign.mode = "2 cores: campaign";
  campaign.cores = 2;
  single.mode = "2 cores: one run";
  single.cores = 2;
  LammpsRequest r;
  if (o.lammps) {
    const auto masses = sys.species.masses(kLammpsQualityFactor);
    r.data = fmt::format("start_{}d_{}.data", D, n);
    write_lammps_data((work / r.data).string(), sys.particles, sys.box.length(0.0), masses[0],
                      masses[1], fmt::format("jam bench throughput, dim {} n {}", D, n));
    r.directory = work;
    r.reference = o.reference_dir;
    r.dim = D;
    r.rate = kRate;
    r.dt = 0.8 * 4 * kLammpsQualityFactor * kLammpsQualityFactor / D;
    r.steps = std::max(10L, steps / 3);
    r.every = r.steps;
    one.lammps_steps = campaign.lammps_steps = single.lammps_steps = r.steps;
  }
  // Each repeat measures every entry once, jam and LAMMPS in turn, so that a change of the
  // machine's load hits both; the medians over repeats are reported.
  std::vector<double> jam1, jam2, jam2m, lmp1, lmp2c, lmp2m;
  const int single_run_threads = std::min(2, available_threads());
  for (int rep = 0; rep < o.repeats; ++rep) {
    {
      System<D> copy = sys;
      const std::size_t builds = copy.neighbors.builds();
      const double wall = timed_steps(copy, steps);
      jam1.push_back(static_cast<double>(steps * n) / wall);
      one.jam_bytes = static_cast<double>(copy.memory_bytes()) / static_cast<double>(n);
      one.builds_per_step =
          static_cast<double>(copy.neighbors.builds() - builds) / static_cast<double>(steps);
    }
    if (o.two_cores) {
      System<D> a = sys, b = sys;
      const auto start = Clock::now();
      side_by_side([&] { timed_steps(b, steps); }, [&] { timed_steps(a, steps); });
      const double wall = std::chrono::duration<double>(Clock::now() - start).count();
      jam2.push_back(static_cast<double>(2 * steps * n) / wall);
      System<D> threaded = sys;
      threaded.set_threads(single_run_threads);
      jam2m.push_back(static_cast<double>(steps * n) / timed_steps(threaded, steps));
    }
    if (!o.lammps) continue;
    r.log = "one.log";
    r.ranks = 1;
    const LammpsResult l1 = run_lammps(r);
    lmp1.push_back(static_cast<double>(l1.steps * n) / l1.loop_seconds);
    one.lammps_bytes = l1.memory_mbytes * 1048576.0 / static_cast<double>(n);
    if (!o.two_cores) continue;
    // Two independent LAMMPS runs at once, then one run on 2 MPI ranks.
    LammpsRequest ra = r, rb = r;
    ra.log = "campaign_a.log";
    rb.log = "campaign_b.log";
    LammpsResult la, lb;
    side_by_side([&] { lb = run_lammps(rb); }, [&] { la = run_lammps(ra); });
    lmp2c.push_back(static_cast<double>(r.steps * n) *
                    (1.0 / la.loop_seconds + 1.0 / lb.loop_seconds));
    LammpsRequest rm = r;
    rm.log = "mpi.log";
    rm.ranks = 2;
    const LammpsResult lm = run_lammps(rm);
    lmp2m.push_back(static_cast<double>(lm.steps * n) / lm.loop_seconds);
    single.lammps_bytes = lm.memory_mbytes * 2 * 1048576.0 / static_cast<double>(n);
  }
  one.jam = median(jam1);
  single.jam = median(jam2m);
  campaign.jam = median(jam2);
  one.lammps = median(lmp1);
  campaign.lammps = median(lmp2c);
  single.lammps = median(lmp2m);
  campaign.jam_bytes = single.jam_bytes = one.jam_bytes;
  campaign.builds_per_step = single.builds_per_step = one.builds_per_step;
  campaign.lammps_bytes = one.lammps_bytes;
  if (o.lammps) fs::remove(work / r.data);
  rows.push_back(one);
  if (o.two_cores) {
    rows.push_back(campaign);
    rows.push_back(single);
  }
  fmt::print(stderr, "  {}D N = {}: jam {:.3g}, LAMMPS {:.3g} particle-steps/s (1 core)\n", D, n,
             one.jam, one.lammps);
}

}  // namespace

std::vector<ThroughputRow> run_throughput(const ThroughputOptions& o) {
  if (o.n_min < 64 || o.n_min % 2 != 0)
    throw std::runtime_error(fmt::format("--n-min {}: must be even and at least 64", o.n_min));
  if (o.n_max < o.n_min)
    throw std::runtime_error(fmt::format("--n-max {}: must be at least --n-min", o.n_max));
  if (o.repeats < 1) throw std::runtime_error(fmt::format("--repeats {}: at least 1", o.repeats));
  if (!(o.seconds > 0))
    throw std::runtime_error(fmt::format("--seconds {:g}: must be positive", o.seconds));
  for (int d : o.dims)
    if (d != 2 && d != 3) throw std::runtime_error(fmt::format("--dims {}: 2 or 3", d));
  const bool lammps = o.lammps && lmp_available();
  if (o.lammps && !lammps) fmt::print(stderr, "jam bench: no lmp on the PATH, jam only\n");
  ThroughputOptions opts = o;
  opts.lammps = lammps;
  const fs::path work = make_temp_directory("jam-bench-throughput");
  std::vector<ThroughputRow> rows;
  try {
    for (int d : o.dims) {
      for (std::int64_t n = o.n_min; n <= o.n_max; n *= 4) {
        if (d == 2) measure_size<2>(opts, n, work, rows);
        if (d == 3) measure_size<3>(opts, n, work, rows);
      }
    }
  } catch (...) {
    if (!std::getenv("JAM_BENCH_KEEP")) fs::remove_all(work);
    throw;
  }
  fs::remove_all(work);
  return rows;
}

void write_throughput_report(const ThroughputOptions& o, const std::vector<ThroughputRow>& rows) {
  fs::create_directories(o.out_dir);
  std::string csv =
      "dim,n,mode,cores,steps,jam_particle_steps_per_s,lammps_particle_steps_per_s,ratio,"
      "jam_bytes_per_particle,lammps_bytes_per_particle,jam_builds_per_step\n";
  std::string md = fmt::format(
      "# Throughput: jam against LAMMPS\n\n`{}`\n\nMachine: {}. Date: {}.\n\n"
      "Particle-steps per second (all runs of a mode together), median of {} repeats; ratio = jam "
      "/ LAMMPS in the same "
      "run. jam: overdamped Euler, dt 0.01; LAMMPS: inertial Q = 0.1 at 0.8 x its stability "
      "bound. '2 cores: one run': jam with --threads 2 (OpenMP, partial forces summed in a "
      "fixed order), LAMMPS on 2 MPI ranks.\n\n"
      "| D | N | mode | jam | LAMMPS | ratio | jam B/particle | LAMMPS B/particle |\n"
      "|---|---|---|---|---|---|---|---|\n",
      o.command, machine_description(), utc_now(), o.repeats);
  for (const auto& r : rows) {
    const double ratio = r.lammps > 0 ? r.jam / r.lammps : 0.0;
    csv += fmt::format("{},{},{},{},{},{:.6g},{:.6g},{:.4g},{:.4g},{:.4g},{:.4g}\n", r.dim, r.n,
                       r.mode, r.cores, r.steps, r.jam, r.lammps, ratio, r.jam_bytes,
                       r.lammps_bytes, r.builds_per_step);
    md += fmt::format("| {} | {} | {} | {:.3g} | {} | {} | {:.0f} | {} |\n", r.dim, r.n, r.mode,
                      r.jam, r.lammps > 0 ? fmt::format("{:.3g}", r.lammps) : "-",
                      r.lammps > 0 ? fmt::format("{:.2f}", ratio) : "-", r.jam_bytes,
                      r.lammps > 0 ? fmt::format("{:.0f}", r.lammps_bytes) : "-");
  }
  const std::string base = (fs::path(o.out_dir) / "throughput").string();
  write_text_file(base + ".csv", csv);
  write_text_file(base + ".md", md);
  plot("throughput", base + ".csv", base + ".png");
}

}  // namespace jam::bench
