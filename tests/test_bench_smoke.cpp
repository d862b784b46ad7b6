// `jam bench throughput` and `jam bench accuracy` at tiny sizes: they run, write their tables,
// and every number in them is finite and positive where it must be. No timing is asserted
// (timings on a shared machine are not reproducible); the benchmarks' results live in
// reports/benchmarks/.
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "process.hpp"
#include "scratch.hpp"

namespace fs = std::filesystem;

namespace {

const jam::test::ScratchDir kDir("bench-smoke");

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    BOOST_FAIL("no column " + name);
    return 0;
  }
};

Csv read_csv(const fs::path& path) {
  std::ifstream in(path);
  Csv csv;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    if (csv.header.empty()) {
      csv.header = cells;
    } else {
      BOOST_REQUIRE_EQUAL(cells.size(), csv.header.size());
      csv.rows.push_back(cells);
    }
  }
  return csv;
}

/// Runs `jam <args>`; a failure shows the command's output in the test log.
int run_jam(const std::string& args) {
  const auto o = jam::test::run_jam_logged(kDir / "out.txt", args);
  if (o.status != 0)
    BOOST_TEST_MESSAGE("jam " << args << " exited " << o.status << ":\n" << o.output);
  return o.status;
}

bool have_lmp() {
  return !jam::find_program("lmp").empty();
}

}  // namespace

BOOST_AUTO_TEST_CASE(throughput_table_is_complete_and_positive) {
  const fs::path out = kDir / "throughput";
  BOOST_REQUIRE_EQUAL(run_jam("bench throughput --dims 2,3 --n-min 256 --n-max 256 --seconds 0.02 "
                              "--repeats 1 --out-dir " +
                              out.string()),
                      0);
  const Csv csv = read_csv(out / "throughput.csv");
  // 2 dimensions x 1 size x 3 modes.
  BOOST_REQUIRE_EQUAL(csv.rows.size(), 6u);
  const bool lmp = have_lmp();
  for (const auto& row : csv.rows) {
    const double jam_speed = std::stod(row[csv.column("jam_particle_steps_per_s")]);
    const double bytes = std::stod(row[csv.column("jam_bytes_per_particle")]);
    BOOST_TEST((std::isfinite(jam_speed) && jam_speed > 0));
    // Positions, forces, types, ids and a half list of ~2-6 neighbours: tens to hundreds of
    // bytes per particle; outside [20, 2000] the accounting itself would be broken.
    BOOST_TEST((bytes > 20 && bytes < 2000));
    if (lmp) {
      const double l = std::stod(row[csv.column("lammps_particle_steps_per_s")]);
      BOOST_TEST((std::isfinite(l) && l > 0));
    }
  }
  BOOST_TEST(fs::file_size(out / "throughput.md") > 0);
}

BOOST_AUTO_TEST_CASE(accuracy_table_is_complete_and_the_reference_converges) {
  const fs::path out = kDir / "accuracy";
  BOOST_REQUIRE_EQUAL(
      run_jam("bench accuracy --dims 2 --n 128 --rates 1e-2 --seeds 2 --euler-dt 0.02 0.05 "
              "--heun-dt 0.05 --chebyshev-tolerance 1e-3 --verlet-q 0.1 --reference-dt 0.02 "
              "--jobs 2 --out-dir " +
              out.string()),
      0);
  const Csv csv = read_csv(out / "accuracy.csv");
  // 3 reference levels, 2 Euler, 1 Heun, 1 Chebyshev, jam Verlet, and with lmp LAMMPS read
  // two ways; the whole `jam sim` processes: defaults and landed from the relaxed starts, and
  // from the unrelaxed ones 3 reference levels, defaults, landed and no transient tolerance.
  BOOST_REQUIRE_EQUAL(csv.rows.size(), have_lmp() ? 18u : 16u);
  int processes = 0, unrelaxed = 0;
  double euler_coarse = 0, euler_fine = 0;
  for (const auto& row : csv.rows) {
    const double wall = std::stod(row[csv.column("wall_median_s")]);
    const double err = std::stod(row[csv.column("max_error")]);
    BOOST_TEST((std::isfinite(wall) && wall > 0));
    BOOST_TEST((std::isfinite(err) && err >= 0 && err < 0.5));
    if (row[csv.column("integrator")] == "chebyshev") {
      BOOST_TEST(std::stod(row[csv.column("tolerance")]) == 1e-3);
    }
    if (row[csv.column("integrator")] == "euler") {
      (std::stod(row[csv.column("dt")]) > 0.03 ? euler_coarse : euler_fine) = err;
    }
    if (row[csv.column("engine")] == "jam-process") {
      ++processes;
      // The whole process takes longer than nothing, and what it read at the grid points is
      // the compression the reference made of the same start.
      BOOST_TEST(std::stod(row[csv.column("process_wall_median_s")]) > 0.0);
      BOOST_TEST(err < 0.05);
    }
    unrelaxed += row[csv.column("start")] == "unrelaxed";
  }
  BOOST_TEST(processes == 5);
  BOOST_TEST(unrelaxed == 6);
  // Euler is first order: 2.5x the step gives about 2.5x the error. Both are systematic
  // errors far above the seeds' noise at this rate (1e-3 and above); a factor 1.5 allows
  // for the mixture of orders that chaotic divergence adds.
  BOOST_TEST(euler_coarse > 1.5 * euler_fine);
  BOOST_TEST(fs::file_size(out / "accuracy.md") > 0);
}

// The whole processes in 3D (each `jam sim` told its dimension: a 3D data file read as 2D is
// refused), without LAMMPS.
BOOST_AUTO_TEST_CASE(whole_processes_run_in_3d) {
  const fs::path out = kDir / "accuracy-3d";
  BOOST_REQUIRE_EQUAL(
      run_jam("bench accuracy --dims 3 --n 128 --rates 1e-2 --seeds 1 --euler-dt 0.05 "
              "--heun-dt 0.05 --chebyshev-tolerance 1e-3 --verlet-q 0.1 --reference-dt 0.02 "
              "--no-lammps --out-dir " +
              out.string()),
      0);
  const Csv csv = read_csv(out / "accuracy.csv");
  int processes = 0;
  for (const auto& row : csv.rows) {
    if (row[csv.column("engine")] != "jam-process") continue;
    ++processes;
    BOOST_TEST(row[csv.column("dim")] == "3");
    BOOST_TEST(std::stod(row[csv.column("max_error")]) < 0.05);
  }
  BOOST_TEST(processes == 5);
}

BOOST_AUTO_TEST_CASE(bad_options_are_rejected_in_one_line) {
  BOOST_TEST(run_jam("bench throughput --n-min 3 --out-dir " + (kDir / "bad").string()) != 0);
  BOOST_TEST(!fs::exists(kDir / "bad" / "throughput.csv"));
  BOOST_TEST(run_jam("bench accuracy --seeds 0 --out-dir " + (kDir / "bad").string()) != 0);
  BOOST_TEST(run_jam("bench accuracy --dims 4 --out-dir " + (kDir / "bad").string()) != 0);
  BOOST_TEST(run_jam("bench accuracy --process-repeats 0 --out-dir " + (kDir / "bad").string()) !=
             0);
  BOOST_TEST(!fs::exists(kDir / "bad" / "accuracy.csv"));
}
