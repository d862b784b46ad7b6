#include "checks/lammps_check.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "checks/lammps_runner.hpp"
#include "sim/dynamics/system.hpp"
#include "sim/initial_state.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/model/contact_laws.hpp"
#include "sim/observables/observables.hpp"
#include "sim/run/compression_run.hpp"
#include "sim/version.hpp"

namespace jam::checks {
namespace fs = std::filesystem;
namespace {

constexpr double kRate = 1e-3, kDt = 0.005, kQualityFactor = 0.1;
constexpr int kSteps = 400;

// Tolerances. Positions: round-off (1e-16 L per step, operations in another order) and the
// r^2-spaced force table (relative error ~1e-11 for 1e5 entries), amplified only mildly over
// t = 2: measured 4e-12; an error in the step order gives ~5e-6. Pressure and energy: LAMMPS
// interpolates energy and force in its table; at the small overlaps of this start (~1e-3) that
// is ~1e-7 relative (the measurement), 1e-5 leaves a margin and still catches a wrong
// box convention (5e-3) or a wrong drag (> 1e-3).
constexpr double kPositionTolerance = 1e-9, kRelativeTolerance = 1e-5;

struct LammpsResult {
  double virial_pressure = NAN, energy_per_atom = NAN, contacts_per_particle = NAN;
  std::string end_data;  // path of the final configuration
};

std::string today() {
  const std::time_t now = std::time(nullptr);
  char text[16];
  std::strftime(text, sizeof text, "%Y-%m-%d", std::gmtime(&now));
  return text;
}

LammpsResult parse_log(const fs::path& log, const fs::path& end_data) {
  std::ifstream in(log);
  LammpsResult r;
  r.end_data = end_data.string();
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.rfind("Step", 0) == 0 && line.find("c_virial") != std::string::npos) {  // header
      header = true;
      continue;
    }
    if (!header) continue;
    std::istringstream row(line);
    long step = -1;
    double time = 0, p = 0, pe = 0, z = NAN;
    if (row >> step >> time >> p >> pe && step == kSteps) {
      r.virial_pressure = p;
      r.energy_per_atom = pe;
      if (row >> z) r.contacts_per_particle = z;
    }
    if (line.rfind("Loop time", 0) == 0) header = false;
  }
  if (!std::isfinite(r.virial_pressure))
    throw std::runtime_error(fmt::format("{}: no thermo line for step {}", log.string(), kSteps));
  return r;
}

/// The stored result and work directory of a law: "inertial-2d" for the paper's harmonic law
/// (the name it has always had), "inertial-hertzian-2d" for another.
template <class Contact>
std::string case_directory(const char* prefix, int dim) {
  const std::string law = std::string(Contact::kName) == HarmonicContact::kName
                              ? std::string()
                              : std::string(Contact::kName) + "-";
  return fmt::format("{}-{}{}d", prefix, law, dim);
}

template <int D, class Contact>
std::vector<Verdict> compare_dimension(const LammpsCheckOptions& o) {
  const fs::path ref(o.reference_directory);
  const fs::path stored = ref / case_directory<Contact>("inertial", D);
  const fs::path dir = fs::path(o.work_directory) / case_directory<Contact>("lammps", D);
  fs::create_directories(dir);
  const std::string label = fmt::format("{}D {}inertial Q={:g} dt={:g} x{}", D,
                                        std::string(Contact::kName) == HarmonicContact::kName
                                            ? std::string()
                                            : std::string(Contact::kName) + " ",
                                        kQualityFactor, kDt, kSteps);
  const bool live = o.use_lmp && lmp_available();
  std::vector<Verdict> out;
  if (!live && !fs::exists(stored / "lammps.log")) {
    out.push_back(inconclusive("lammps", label, "no lmp on the PATH and no stored LAMMPS result"));
    return out;
  }
  // The start: the stored one (so the stored LAMMPS result applies), or a fresh one when
  // regenerating.
  if (o.regenerate || !fs::exists(stored / "start.data")) {
    write_relaxed_start({D, D == 2 ? 0.80 : 0.60, kQualityFactor, kDt, "inertial", "1e-6", 17},
                        dir / "start.data");
  } else {
    copy_file_atomically((stored / "start.data").string(), (dir / "start.data").string());
  }
  if (live) {
    run_lammps(dir, ref, D, kRate, kDt, kSteps, kSteps / 8, "start.data", "lammps.log",
               "lammps_end.data", Contact::kName);
  }
  const fs::path from = live ? dir : stored;
  const LammpsResult lmp = parse_log(from / "lammps.log", from / "lammps_end.data");
  if (o.regenerate && live) {
    fs::create_directories(stored);
    for (const char* f : {"start.data", "lammps.log", "lammps_end.data"}) {
      copy_file_atomically((dir / f).string(), (stored / f).string());
    }
    std::ofstream(stored / "provenance.toml")
        << fmt::format("# Stored LAMMPS result for `jam check lammps` ({}D)\n", D) << "lammps = \""
        << lammps_version(dir / "lammps.log") << "\"\n"
        << "input = \"reference/lammps/compress_inertial.in with the " << Contact::kName
        << " table of sim/io/lammps_table.hpp\"\n"
        << fmt::format("rate = {:g}\ndt = {:g}\nq = {:g}\nsteps = {}\n", kRate, kDt, kQualityFactor,
                       kSteps)
        << "regenerate = \"jam check lammps DIR --regenerate-reference (needs lmp)\"\n"
        << "jam_version = \"" << kVersion << "\"\n"
        << "date = \"" << today() << "\"\n";
  }

  // jam on the same start.
  const auto start = read_lammps_data<D>((dir / "start.data").string());
  const Species<D> species;
  const double phi0 =
      total_particle_volume(start.particles, species) / std::pow(start.box_length, D);
  SimConfig b;
  b.dim = D;
  b.read_lammps_data = (dir / "start.data").string();
  b.n_given = b.phi_init_given = false;
  b.relax = false;
  b.dynamics = "inertial";
  b.quality_factor = kQualityFactor;
  b.dt = kDt;
  b.contact = Contact::kName;
  b.compression_rate = kRate;
  b.phi_stop = phi0 * std::exp(D * kRate * kSteps * kDt);
  b.quiet = true;
  b.checkpoint_interval = 0;
  b.out = (dir / "jam_run.h5").string();
  b.write_final_lammps_data = (dir / "jam_end.data").string();
  run_compression(b);

  const auto mine = read_lammps_data<D>(b.write_final_lammps_data);
  const auto theirs = read_lammps_data<D>(lmp.end_data);
  std::map<std::uint32_t, std::size_t> where;
  for (std::size_t i = 0; i < theirs.particles.size(); ++i) where[theirs.particles.id[i]] = i;
  double worst = 0.0;
  for (std::size_t i = 0; i < mine.particles.size(); ++i) {
    const std::size_t j = where.at(mine.particles.id[i]);
    for (int d = 0; d < D; ++d) {
      worst = std::max(worst,
                       std::abs(minimum_image(mine.particles.s[d][i] - theirs.particles.s[d][j])) *
                           mine.box_length);
    }
  }
  // LAMMPS's thermo at the last step: forces (and energy) at the box before the deformation,
  // volume after it.
  System<D, Contact> sys(mine.particles, species, CompressingBox<D>{}, 0.3);
  sys.box.particle_volume = total_particle_volume(mine.particles, species);
  sys.box.initial_length = CompressingBox<D>::length_for_packing(sys.box.particle_volume, phi0) *
                           std::exp(-kRate * (kSteps - 1) * kDt);
  const auto before = measure(sys, 0.0, false);
  const double volume_ratio = std::pow(std::exp(-kRate * kDt), D);
  const double pressure = before.pressure / volume_ratio;

  const std::string source = live ? "LAMMPS run now" : "stored LAMMPS result";
  auto verdict = [&](const std::string& what, double statistic, double tolerance,
                     const std::string& reason) {
    Verdict v;
    v.check = "lammps";
    v.case_name = label + ": " + what;
    // Positions and contacts are absolute differences, in their own units; pressure and
    // energy relative ones (the check's unit).
    v.statistic_name = what == "positions"  ? "max |x_jam - x_lammps|"
                       : what == "contacts" ? "|Z_jam - Z_lammps|"
                                            : "relative difference";
    if (what == "positions") v.unit = "d_s";
    if (what == "contacts") v.unit = "contacts per particle";
    v.statistic = statistic;
    v.threshold = tolerance;
    v.detectable = tolerance;
    // A deterministic comparison: the difference is what it is, and the tolerance (round-off
    // and the force table, above) is its margin.
    v.margin = tolerance;
    v.excluded_above = statistic;
    v.status = statistic <= tolerance ? "pass" : "fail";
    v.reason = reason + " (" + source + ")";
    return v;
  };
  out.push_back(verdict("positions", worst, kPositionTolerance,
                        fmt::format("max |x_jam - x_lammps| = {:.3g}", worst)));
  out.push_back(verdict("pressure", std::abs(pressure / lmp.virial_pressure - 1),
                        kRelativeTolerance,
                        fmt::format("jam {:.10g}, LAMMPS {:.10g}", pressure, lmp.virial_pressure)));
  out.push_back(verdict(
      "energy", std::abs(before.energy_per_particle / lmp.energy_per_atom - 1), kRelativeTolerance,
      fmt::format("jam {:.10g}, LAMMPS {:.10g}", before.energy_per_particle, lmp.energy_per_atom)));
  // Contacts are counted by LAMMPS per type pair (compute coord/atom, r < d_ij): the same
  // integers unless a pair sits within the position difference (~1e-11) of contact.
  out.push_back(verdict("contacts",
                        std::abs(before.contacts_per_particle - lmp.contacts_per_particle), 1e-12,
                        fmt::format("Z jam {:.6f}, LAMMPS {:.6f}", before.contacts_per_particle,
                                    lmp.contacts_per_particle)));
  return out;
}

}  // namespace

std::vector<Verdict> lammps_check(const LammpsCheckOptions& o) {
  std::vector<Verdict> out;
  // Every contact law, in 2D and 3D.
  auto compare_law = [&]<class Contact>() {
    for (const auto& v : {compare_dimension<2, Contact>(o), compare_dimension<3, Contact>(o)})
      out.insert(out.end(), v.begin(), v.end());
  };
  std::apply([&](auto... law) { (compare_law.template operator()<decltype(law)>(), ...); },
             ContactLaws{});
  const auto overdamped = lammps_overdamped_check(o);
  out.insert(out.end(), overdamped.begin(), overdamped.end());
  return out;
}

}  // namespace jam::checks
