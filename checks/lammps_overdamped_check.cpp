// jam's default overdamped dynamics against LAMMPS's inertial dynamics at small Q (0.03, where
// the paper's model is in its overdamped limit): the same four relaxed starts compressed
// through jamming at rate 1e-3 (2D: phi 0.80 -> 0.86, 3D: 0.60 -> 0.68), pressure against phi
// compared sample by sample. Single trajectories of chaotic dynamics drift apart, so the
// verdict is on the mean over samples of Delta p/p = 2 (p_jam - p_lammps)/(p_jam + p_lammps):
// it passes when max_phi |<Delta>| <= 0.5% + 3 standard errors. What the two may legitimately
// differ by at this rate: LAMMPS at Q = 0.03 is within 0.01% of the overdamped limit, its thermo
// uses pre-deformation forces (<0.2% at dt = 0.5 * 2 m_s/gamma_s), jam's default (Heun at
// dt = 0.1) errs by less than 1e-5 at rate 1e-3 (docs/performance.md, Accuracy); measured
// together: 0.06% (2D) and 0.03% (3D), 0.08% and 0.09% with Euler at dt = 0.01. 0.5% keeps
// a margin of 5x or more; a wrong drag, time unit or host-flow term moves the pressure by 10%
// or more.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "checks/lammps_check.hpp"
#include "checks/lammps_runner.hpp"
#include "checks/margin.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_import.hpp"
#include "sim/run/compression_run.hpp"
#include "stats/averages.hpp"

namespace jam::checks {
namespace fs = std::filesystem;
namespace {

constexpr double kOverdampedRate = 1e-3, kOverdampedQualityFactor = 0.03;
// The band of a sample mean of 4 chaotic trajectories: 3 standard errors.
constexpr double kErrors = 3.0;
constexpr int kSamples = 4;

template <int D>
Verdict compare_overdamped(const LammpsCheckOptions& o) {
  const double phi0 = D == 2 ? 0.80 : 0.60, phi_stop = D == 2 ? 0.86 : 0.68;
  const fs::path ref(o.reference_directory), stored = ref / fmt::format("overdamped-{}d", D);
  const fs::path dir = fs::path(o.work_directory) / fmt::format("overdamped-{}d", D);
  fs::create_directories(dir);
  const std::string label = fmt::format("{}D overdamped vs LAMMPS Q={:g}, {} samples", D,
                                        kOverdampedQualityFactor, kSamples);
  const bool live = o.use_lmp && lmp_available();
  if (!live && !fs::exists(stored / "lammps_0.log")) {
    return inconclusive("lammps", label, "no lmp on the PATH and no stored LAMMPS result");
  }
  // LAMMPS's step: half its stability bound 2 m_s/gamma_s = 4 Q^2 / D.
  const double dt_lammps = 0.5 * 4 * kOverdampedQualityFactor * kOverdampedQualityFactor / D;
  const double t_stop = std::log(phi_stop / phi0) / (D * kOverdampedRate);
  const long steps = static_cast<long>(std::ceil(t_stop / dt_lammps));
  std::vector<std::vector<double>> deltas;                  // [sample][grid point]
  std::vector<std::vector<double>> p_jam_grid, p_lmp_grid;  // the same, for the report's overlay
  std::vector<double> grid;
  for (double phi = phi0 + 0.004; phi <= phi_stop - 0.002 + 1e-12; phi += 0.002)
    grid.push_back(phi);
  for (int k = 0; k < kSamples; ++k) {
    const std::string start = fmt::format("start_{}.data", k),
                      log = fmt::format("lammps_{}.log", k);
    if (o.regenerate || !fs::exists(stored / start)) {
      // Relaxed with jam's overdamped dynamics; masses of Q for LAMMPS.
      write_relaxed_start({D, phi0, kOverdampedQualityFactor, 0.01, "overdamped", "1e-12",
                           static_cast<std::uint64_t>(100 + k)},
                          dir / start);
    } else {
      copy_file_atomically((stored / start).string(), (dir / start).string());
    }
    if (live)
      run_lammps(dir, ref, D, kOverdampedRate, dt_lammps, steps, steps / 60, start, log,
                 fmt::format("end_{}.data", k));
    const LammpsThermo lmp = read_lammps_thermo(((live ? dir : stored) / log).string());
    // jam, overdamped (the default integrator and dt), from the same start.
    SimConfig b;
    b.dim = D;
    b.read_lammps_data = (dir / start).string();
    b.n_given = b.phi_init_given = false;
    b.relax = false;
    b.compression_rate = kOverdampedRate;
    b.phi_stop = phi_stop;
    b.phi_step = 0.001;
    b.quiet = true;
    b.checkpoint_interval = 0;
    b.out = (dir / fmt::format("jam_{}.h5", k)).string();
    run_compression(b);
    const h5::File f = h5::File::open_read(b.out);
    const auto phi_jam = f.read_dataset("packing_fraction");
    const auto p_jam = f.read_dataset("pressure", h5::exactly(phi_jam.size()));
    const double phi_start = f.read_attribute_double("phi_init");
    std::vector<double> phi_lmp;
    for (double t : lmp.time) phi_lmp.push_back(phi_start * std::exp(D * kOverdampedRate * t));
    std::vector<double> row, a_row, b_row;
    for (double phi : grid) {
      const double a = stats::interpolate(phi_jam, p_jam, phi),
                   b2 = stats::interpolate(phi_lmp, lmp.pressure, phi);
      row.push_back(2 * (a - b2) / (a + b2));
      a_row.push_back(a);
      b_row.push_back(b2);
    }
    deltas.push_back(std::move(row));
    p_jam_grid.push_back(std::move(a_row));
    p_lmp_grid.push_back(std::move(b_row));
  }
  if (o.regenerate && live) {
    fs::create_directories(stored);
    for (int k = 0; k < kSamples; ++k) {
      for (const auto& f : {fmt::format("start_{}.data", k), fmt::format("lammps_{}.log", k)}) {
        copy_file_atomically((dir / f).string(), (stored / f).string());
      }
    }
    std::ofstream(stored / "provenance.toml")
        << fmt::format(
               "# Stored LAMMPS results for `jam check lammps`, overdamped comparison ({}D)\n", D)
        << "lammps = \"" << lammps_version(dir / "lammps_0.log") << "\"\n"
        << fmt::format("q = {:g}\ndt = {:.17g}\nrate = {:g}\nsteps = {}\nsamples = {}\n",
                       kOverdampedQualityFactor, dt_lammps, kOverdampedRate, steps, kSamples)
        << "regenerate = \"jam check lammps DIR --regenerate-reference (needs lmp)\"\n";
  }
  // Mean and standard error over samples at each packing; the worst point decides.
  double worst = 0.0, worst_error = 0.0, worst_phi = 0.0, allowed = 0.0, surely = 0.0;
  bool detected = false;
  std::vector<double> mean_delta, mean_error, mean_p_jam, mean_p_lmp;
  for (std::size_t g = 0; g < grid.size(); ++g) {
    double mean = 0.0, ss = 0.0, pa = 0.0, pb = 0.0;
    for (int k = 0; k < kSamples; ++k) {
      mean += deltas[k][g] / kSamples;
      pa += p_jam_grid[k][g] / kSamples;
      pb += p_lmp_grid[k][g] / kSamples;
    }
    for (const auto& row : deltas) ss += (row[g] - mean) * (row[g] - mean);
    const double error = std::sqrt(ss / (kSamples - 1) / kSamples);
    mean_delta.push_back(mean);
    mean_error.push_back(error);
    mean_p_jam.push_back(pa);
    mean_p_lmp.push_back(pb);
    if (std::abs(mean) > worst) {
      worst = std::abs(mean);
      worst_error = error;
      worst_phi = grid[g];
    }
    allowed = std::max(allowed, std::abs(mean) + kErrors * error);
    surely = std::max(surely, std::abs(mean) - kErrors * error);
    detected = detected || std::abs(mean) > kErrors * error;
  }
  Verdict v;
  v.check = "lammps";
  v.case_name = label;
  v.statistic_name = "max |<Delta p/p>|";
  v.statistic = worst;
  v.threshold = kErrors * worst_error;
  v.detectable = kErrors * worst_error;
  decide(v, detected, allowed, surely, o.margin);
  v.reason += fmt::format(" (largest mean Delta p/p {} +- {} at phi {:.3f}; {})",
                          effect_text(v, worst), effect_text(v, worst_error), worst_phi,
                          live ? "LAMMPS run now" : "stored LAMMPS result");
  // The overlay and residuals the report draws: sample means on the packing grid.
  v.values = {{"dim", static_cast<double>(D)},
              {"compression_rate", kOverdampedRate},
              {"q", kOverdampedQualityFactor}};
  v.curves = {{"grid", grid},
              {"pressure_jam", mean_p_jam},
              {"pressure_lammps", mean_p_lmp},
              {"delta", mean_delta},
              {"sigma", mean_error}};
  return v;
}

}  // namespace

std::vector<Verdict> lammps_overdamped_check(const LammpsCheckOptions& o) {
  return {compare_overdamped<2>(o), compare_overdamped<3>(o)};
}

}  // namespace jam::checks
