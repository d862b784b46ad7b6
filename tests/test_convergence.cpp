// Numerical convergence as a verdict: `jam campaign converge` writes the campaign that redoes
// part of a campaign at a stricter integrator setting from the same starts (chained rates from
// the campaign's own stored parents, rewritten when gone), and `jam check convergence` judges
// the campaign against it sample by sample. A campaign at the default tolerance passes at the
// 1% margin; one at a planted loose tolerance (0.3) fails; synthetic pairs check the paired
// statistic itself (a planted 3% bias fails, chaos-sized scatter without a bias stays within).
#include <unistd.h>

#include <boost/test/unit_test.hpp>
#include <filesystem>
#include <fstream>
#include <random>

#include "checks/checks.hpp"
#include "checks/regression_check.hpp"
#include "process.hpp"
#include "synthetic_runs.hpp"

namespace fs = std::filesystem;
using jam::test::slurp;
using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

const fs::path kDir = fs::temp_directory_path() / ("jam-convergence-" + std::to_string(::getpid()));

int run_jam(const std::string& args, std::string* output = nullptr) {
  const auto o = jam::test::run_jam_logged(kDir / "log.txt", args);
  if (output) *output = o.output;
  return o.status;
}

/// A tiny chained campaign (N 128 and 256, rates 1e-4 ... 1e-5, 8 samples) at `tolerance`.
fs::path campaign_file(const std::string& name, const std::string& tolerance) {
  const fs::path file = kDir / (name + ".toml");
  std::ofstream(file) << "name = \"" << name << "\"\ndim = 2\nsizes = [128, 256]\n"
                      << "phi_init = [0.70]\nlog10_rates = [-4.0, -4.5, -5.0]\n"
                      << "chain_phi_init = [0, 0.78, 0.79]\nsamples = 8\nphi_stop = 0.86\n"
                      << "phi_step = 0.001\nseed = 3\nrelax_energy = \"1e-14\"\n"
                      << "tolerance = \"" << tolerance << "\"\noutput = \""
                      << (kDir / "runs" / name).string() << "\"\n";
  return file;
}

/// The campaign run and judged against its convergence runs; returns `jam check`'s status.
int converged_status(const std::string& name, const std::string& tolerance, std::string* out) {
  const fs::path file = campaign_file(name, tolerance);
  const std::string dir = (kDir / "runs" / name).string();
  BOOST_TEST_REQUIRE(run_jam("campaign run --quiet " + file.string()) == 0);
  BOOST_TEST_REQUIRE(run_jam("stats " + dir) == 0);
  BOOST_TEST_REQUIRE(run_jam("campaign converge " + file.string() + " --samples 8", out) == 0,
                     *out);
  const fs::path converge = kDir / (name + "-convergence.toml");
  BOOST_TEST_REQUIRE(fs::exists(converge));
  // The parents' starts are gone, as in a snapshot of a finished campaign: rewritten first.
  fs::remove_all(fs::path(dir) / "chain");
  fs::remove_all(fs::path(dir) / "starts");
  BOOST_TEST_REQUIRE(run_jam("campaign run " + converge.string(), out) == 0, *out);
  BOOST_TEST(out->find("rewritten in") != std::string::npos, *out);
  BOOST_TEST_REQUIRE(run_jam("stats " + dir + "-convergence") == 0);
  return run_jam("check convergence " + dir + " --against " + dir + "-convergence", out);
}

/// Paired synthetic sets: the campaign's samples, and the first `redone` of them again with
/// their pressure times (1 + bias) (1 + chaos eps_i), eps per sample and point.
StatsData synthetic(double bias, double chaos, std::size_t redone, StatsData* converged) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  StatsData d;
  d.fit_phi_j = 0.84;
  d.fit_window_min = 0.83;
  d.fit_window_max = 0.85;
  auto rows = runs(10, 0.0, rng);
  d.ensembles.push_back(ensemble(256, 0.4, -6, rows));
  std::vector<std::vector<double>> again(rows.begin(), rows.begin() + static_cast<long>(redone));
  for (auto& r : again)
    for (double& p : r) p /= (1 + bias) * (1 + chaos * g(rng));
  converged->ensembles.push_back(ensemble(256, 0.4, -6, again));
  return d;
}

}  // namespace

BOOST_AUTO_TEST_CASE(paired_statistic_fails_a_bias_and_passes_chaos) {
  CheckOptions o;
  StatsData converged;
  // 3% too high in every sample, 0.1% chaos, 4 samples redone: surely beyond 1%.
  StatsData d = synthetic(0.03, 0.001, 4, &converged);
  for (const auto& v : convergence_check(d, converged, o, {})) {
    BOOST_TEST(v.status == "fail", v.case_name << ": " << v.reason);
    BOOST_TEST(std::abs(v.estimate - 0.03) < 0.005, v.reason);
  }
  // No bias, chaos of 0.3% per point and sample, 4 samples: within 1% everywhere, though the
  // samples' own scatter (10%) is far larger: it cancels in the pairs.
  converged = {};
  d = synthetic(0.0, 0.003, 4, &converged);
  const auto verdicts = convergence_check(d, converged, o, {});
  BOOST_TEST(verdicts.size() == 4u);  // pooled and the three regions
  for (const auto& v : verdicts) BOOST_TEST(v.status == "pass", v.case_name << ": " << v.reason);
  // Nothing redone: one verdict saying how to make the runs.
  const auto none = convergence_check(d, StatsData{}, o, {});
  BOOST_TEST_REQUIRE(none.size() == 1u);
  BOOST_TEST(none[0].reason.find("jam campaign converge") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(default_tolerance_passes_and_a_loose_one_fails) {
  fs::remove_all(kDir);
  fs::create_directories(kDir);
  std::string out;
  BOOST_TEST(converged_status("default", "auto", &out) == 0, out);
  BOOST_TEST(out.find("passed, 0 failed, 0 inconclusive") != std::string::npos, out);
  // Tolerance 0.3: the steps leave a bias of several percent, beyond 1% in every ensemble.
  BOOST_TEST(converged_status("loose", "0.3", &out) == 1, out);
  BOOST_TEST(out.find("the effect surely exceeds the margin") != std::string::npos, out);
  // The written campaign: a tenth of the tolerance, the largest component, the parents'
  // starts; a choice the campaign cannot meet is one line naming it, and nothing written.
  const std::string text = slurp(kDir / "default-convergence.toml");
  BOOST_TEST(text.find("error_norm = 'max'") != std::string::npos, text);
  BOOST_TEST(text.find("chain_starts_from") != std::string::npos, text);
  // The two slowest rates (1e-5, 10^-4.5) with their starts' packings, read from the campaign.
  BOOST_TEST(text.find("chain_phi_init = [ 0.79000000000000004, 0.78000000000000003 ]") !=
                 std::string::npos,
             text);
  const fs::path file = kDir / "default.toml";
  BOOST_TEST(run_jam("campaign converge " + file.string() + " --sizes 512 --out " +
                         (kDir / "x.toml").string(),
                     &out) == 2);
  BOOST_TEST(out.find("size 512") != std::string::npos, out);
  BOOST_TEST(!fs::exists(kDir / "x.toml"));
  BOOST_TEST(run_jam("campaign converge " + file.string(), &out) == 2);  // exists: not replaced
  BOOST_TEST(out.find("exists") != std::string::npos, out);
  // The convergence runs of convergence runs: they would read starts their campaign reads
  // from another; refused, naming the one that chains them.
  const fs::path again = kDir / "again.toml";
  BOOST_TEST_REQUIRE(run_jam("campaign converge " + (kDir / "default-convergence.toml").string() +
                                 " --samples 2 --out " + again.string(),
                             &out) == 0,
                     out);
  BOOST_TEST(run_jam("campaign run " + again.string(), &out) == 2, out);
  BOOST_TEST(out.find("reads its own starts from") != std::string::npos, out);
  // The parent campaign not found (moved; or a relative chain_starts_from read from another
  // directory): the chained runs' starts cannot be judged, and status says so by name.
  fs::rename(kDir / "runs" / "default", kDir / "runs" / "default-moved");
  run_jam("campaign status " + (kDir / "runs" / "default-convergence").string(), &out);
  BOOST_TEST(out.find("its start cannot be judged from here") != std::string::npos, out);
  fs::remove_all(kDir);
}

// A fixed-step campaign is redone by its dynamics' error-controlled integrator (read from the
// integrator list, not named by hand), without the campaign's step; a dynamics that has none
// is refused in one line, and nothing is written.
BOOST_AUTO_TEST_CASE(fixed_step_campaigns_are_redone_by_the_adaptive_integrator) {
  fs::create_directories(kDir);
  auto write = [](const std::string& name, const std::string& keys) {
    const fs::path file = kDir / (name + ".toml");
    std::ofstream(file) << "name = \"" << name << "\"\ndim = 2\nsizes = [128]\n"
                        << "phi_init = [0.70]\nlog10_rates = [-4.0]\nsamples = 4\n"
                        << "phi_stop = 0.86\nseed = 3\n" << keys << "output = \""
                        << (kDir / "runs" / name).string() << "\"\n";
    return file;
  };
  std::string out;
  const fs::path heun = write("heun", "integrator = \"heun\"\ndt = 0.05\n");
  BOOST_TEST_REQUIRE(run_jam("campaign converge " + heun.string() + " --samples 2", &out) == 0,
                     out);
  const std::string text = slurp(kDir / "heun-convergence.toml");
  BOOST_TEST(text.find("integrator = 'chebyshev'") != std::string::npos, text);
  BOOST_TEST(text.find("dt = ") == std::string::npos, text);
  const fs::path inertial = write("inertial", "dynamics = \"inertial\"\ndt = 0.001\n");
  BOOST_TEST(run_jam("campaign converge " + inertial.string() + " --samples 2", &out) == 2, out);
  BOOST_TEST(out.find("dynamics 'inertial' has no error-controlled integrator") !=
                 std::string::npos,
             out);
  BOOST_TEST(!fs::exists(kDir / "inertial-convergence.toml"));
  fs::remove_all(kDir);
}
