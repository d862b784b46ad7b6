#include "bench/process_runs.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "sim/initial_state.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/install_paths.hpp"
#include "sim/io/process.hpp"

namespace jam::bench {
namespace fs = std::filesystem;

void require_on_grid(const std::array<double, 3>& phi) {
  for (double p : phi) {
    const double k = p / kCampaignPhiStep;
    if (std::abs(k - std::round(k)) > 1e-6) {
      throw std::runtime_error(fmt::format(
          "packing {:g} is not on the output grid (multiples of {:g})", p, kCampaignPhiStep));
    }
  }
}

RunResult run_jam_process(const fs::path& dir, int dim, const std::string& data,
                          const std::string& out, double rate,
                          const std::vector<std::string>& extra, const std::array<double, 3>& phi) {
  std::vector<std::string> argv = {(executable_directory() / "jam").string(),
                                   "sim",
                                   "--dim",
                                   std::to_string(dim),
                                   "--read-lammps-data",
                                   data,
                                   "--relax",
                                   "0",
                                   "--rate",
                                   fmt::format("{:.17g}", rate),
                                   "--phi-stop",
                                   fmt::format("{:.17g}", phi[2]),
                                   "--phi-step",
                                   fmt::format("{:g}", kCampaignPhiStep)};
  argv.insert(argv.end(), extra.begin(), extra.end());
  for (const char* a : {"--out", out.c_str(), "--quiet", "--checkpoint-interval", "0"})
    argv.emplace_back(a);
  ProcessOptions where;
  where.working_directory = dir;
  where.stdout_file = where.stderr_file = (dir / (out + ".log")).string();
  const auto start = std::chrono::steady_clock::now();
  const int status = run_program(argv, where);
  RunResult r;
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0) {
    throw std::runtime_error(fmt::format("jam sim failed (exit status {}); see {}", status,
                                         (dir / (out + ".log")).string()));
  }
  const h5::File f = h5::File::open_read((dir / out).string());
  const std::vector<double> packing = f.read_dataset("packing_fraction");
  const std::vector<double> pressure =
      f.read_dataset("pressure", h5::Extent{.length = packing.size()});
  for (int k = 0; k < 3; ++k) {
    bool found = false;
    for (std::size_t i = 0; i < packing.size() && !found; ++i) {
      if (std::abs(packing[i] - phi[k]) < 1e-9) {
        r.pressure[k] = pressure[i];
        found = true;
      }
    }
    if (!found) {
      throw std::runtime_error(
          fmt::format("{}: no output point at packing {:g}", (dir / out).string(), phi[k]));
    }
  }
  fs::remove(dir / out);
  fs::remove(dir / (out + ".log"));
  return r;
}

namespace {
template <int D>
Start unrelaxed(std::int64_t n, std::uint64_t seed, double phi) {
  const Species<D> species;
  RandomStart<D> r = random_start<D>(static_cast<std::size_t>(n), seed, species, phi);
  Start start = start_from(r.particles, r.box_length);
  return start;
}
}  // namespace

Start unrelaxed_start(int dim, std::int64_t n, std::uint64_t seed, double phi) {
  return dim == 2 ? unrelaxed<2>(n, seed, phi) : unrelaxed<3>(n, seed, phi);
}

}  // namespace jam::bench
