// Run files: determinism (bitwise), the documented schema, the output grid, and LAMMPS data
// files written and read back.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "helpers.hpp"
#include "sim/io/atomic_file.hpp"
#include "sim/io/hdf5_file.hpp"
#include "sim/io/lammps_data.hpp"
#include "sim/io/run_file.hpp"
#include "sim/run/compression_run.hpp"

using namespace jam;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() : path(fs::temp_directory_path() / fs::path("jam-test-" + std::to_string(::getpid()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

SimConfig small_run(const std::string& out, int dim = 2) {
  SimConfig c;
  c.dim = dim;
  c.n = 128;
  c.phi_init = dim == 2 ? 0.75 : 0.55;
  c.phi_stop = dim == 2 ? 0.86 : 0.66;
  c.phi_step = 0.005;
  c.compression_rate = 1e-2;
  c.dt = 0.02;
  c.seed = 3;
  c.out = out;
  c.quiet = true;
  return c;
}

}  // namespace

BOOST_AUTO_TEST_CASE(same_seed_gives_bitwise_identical_files) {
  TempDir dir;
  for (const char* integ : {"euler", "heun"}) {
    SimConfig a = small_run(dir / "a.h5"), b = small_run(dir / "b.h5");
    a.integrator = b.integrator = integ;
    a.rattlers = b.rattlers = a.stress = b.stress = true;
    run_compression(a);
    run_compression(b);
    BOOST_TEST((slurp(a.out) == slurp(b.out)));
  }
  SimConfig c = small_run(dir / "c.h5");
  c.seed = 4;
  run_compression(c);
  BOOST_TEST((slurp(c.out) != slurp(dir / "b.h5")));
}

BOOST_AUTO_TEST_CASE(schema_and_output_grid) {
  TempDir dir;
  for (int dim : {2, 3}) {
    SimConfig c = small_run(dir / "run.h5", dim);
    c.rattlers = c.stress = true;
    run_compression(c);
    BOOST_TEST(!fs::exists(jam::AtomicFile::temporary_name(c.out)));
    const h5::File f = h5::File::open_read(c.out);
    BOOST_TEST(f.read_attribute_int("dim") == dim);
    BOOST_TEST(f.read_attribute_int("n") == 128);
    BOOST_TEST(f.read_attribute_int("schema_version") == jam::kRunFileSchemaVersion);
    BOOST_TEST(f.read_attribute_string("units", "pressure") == "k_e/d_s^D");
    BOOST_TEST(f.read_attribute_string("units", "time") == "t0");
    BOOST_TEST(f.read_attribute_string("fingerprint") == jam::fingerprint(c));
    BOOST_TEST(!f.has_attribute("sample"));  // a single run belongs to no campaign
    BOOST_TEST(f.read_attribute_int("complete") == 1);
    BOOST_TEST(f.read_attribute_int("seed") == 3);
    BOOST_TEST(f.read_attribute_double("compression_rate") == 1e-2);
    BOOST_TEST(f.read_attribute_string("integrator") == "chebyshev");  // the overdamped default
    BOOST_TEST(f.read_attribute_string("dynamics") == "overdamped");
    BOOST_TEST(!f.read_attribute_string("version").empty());
    for (const char* a : {"phi_init", "phi_stop", "dt", "q", "diameter_ratio"}) {
      BOOST_TEST(f.has_attribute(a), a);
    }
    const auto phi = f.read_dataset("packing_fraction");
    const auto t = f.read_dataset("time");
    const std::size_t m = phi.size();
    for (const char* name : {"pressure", "contacts_per_particle", "energy_per_particle",
                             "contacts_per_particle_no_rattlers", "rattler_fraction"}) {
      BOOST_TEST(f.read_dataset(name).size() == m, name);
    }
    BOOST_TEST(f.read_dataset("stress").size() == m * dim * dim);
    // First point: the start at t = 0; last point: exactly phi_stop; in between one point
    // per multiple of phi_step, at the first step at or after it (within one step's growth
    // D rate dt phi).
    BOOST_TEST(t.front() == 0.0);
    BOOST_TEST(phi.front() == c.phi_init, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(phi.back() == c.phi_stop, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(m == 2u + 21u);  // 0.755 ... 0.855 (2D) or 0.555 ... 0.655 (3D)
    for (std::size_t k = 1; k + 1 < m; ++k) {
      const double grid = c.phi_init + c.phi_step * static_cast<double>(k);
      BOOST_TEST(phi[k] >= grid * (1 - 1e-12));
      BOOST_TEST(phi[k] - grid <= dim * c.compression_rate * c.dt * phi[k] * 1.0001);
      BOOST_TEST(phi[k] == c.phi_init * std::exp(dim * c.compression_rate * t[k]),
                 boost::test_tools::tolerance(1e-12));
    }
  }
}

BOOST_AUTO_TEST_CASE(lammps_data_round_trip) {
  TempDir dir;
  auto sys = test::random_system<3>(50, 0.5, 9);
  const double L = sys.box.length(0.0);
  write_lammps_data(dir / "c.data", sys.particles, L, 0.1, 0.2744, "test");
  const auto back = read_lammps_data<3>(dir / "c.data");
  BOOST_TEST(back.box_length == L, boost::test_tools::tolerance(1e-15));
  BOOST_TEST_REQUIRE(back.particles.size() == sys.size());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    BOOST_TEST(back.particles.id[i] == sys.particles.id[i]);
    BOOST_TEST(back.particles.type[i] == sys.particles.type[i]);
    for (int d = 0; d < 3; ++d) {
      // x = L (s - 1/2) written with 17 digits, s = (x + L/2) / L read back: a few ulps.
      BOOST_TEST(std::abs(back.particles.s[d][i] - sys.particles.s[d][i]) < 1e-15);
    }
  }
}

BOOST_AUTO_TEST_CASE(run_from_written_data_reproduces_the_run) {
  TempDir dir;
  // Heun, whose fixed steps keep the ulps apart; the Chebyshev integrator's error control
  // would choose other steps for starts a few ulps apart (differences at its tolerance).
  SimConfig a = small_run(dir / "a.h5");
  a.integrator = "heun";
  a.phi_stop = 0.77;
  a.write_lammps_data = dir / "start.data";
  run_compression(a);
  SimConfig b = small_run(dir / "b.h5");
  b.integrator = "heun";
  b.phi_stop = 0.77;
  b.read_lammps_data = a.write_lammps_data;
  b.n_given = b.phi_init_given = false;
  run_compression(b);
  const auto pa = h5::File::open_read(a.out).read_dataset("pressure");
  const auto pb = h5::File::open_read(b.out).read_dataset("pressure");
  BOOST_TEST_REQUIRE(pa.size() == pb.size());
  // The starts differ by a few ulps (text round trip); over this short run the chaotic
  // dynamics amplifies that far less than 1e-8.
  for (std::size_t k = 0; k < pa.size(); ++k) {
    BOOST_TEST(pa[k] == pb[k], boost::test_tools::tolerance(1e-8));
  }
  const h5::File fb = h5::File::open_read(b.out);
  BOOST_TEST(fb.read_attribute_string("initial_configuration") == b.read_lammps_data);
  BOOST_TEST(fb.read_attribute_int("relax_steps") == 0);  // already relaxed
}
