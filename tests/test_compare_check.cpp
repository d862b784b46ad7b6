// The compare check (checks/compare_check.cpp) on synthetic ensembles of two "codes"
// (compare_runs.hpp): equal physics from other seeds, other sample counts (10 against 16) and
// other grids (phi_step 0.0005 against 0.00025, 0.0003 and 0.00033) never fails; a planted
// 10% pressure difference fails at the margin 0.05, on shared and on interpolated grids; a
// jamming-point shift of 0.01 fails compare_jamming; fitted parameters apart fail
// compare_fit and compare_fit_phi_j; ensembles and fits without a partner are named; the grids
// are matched on shared values or interpolated exactly where the curve is linear; and
// `jam check compare DIR --against REF` runs through the baseline path of the registry.
// Where compare judges (short runs, coarse output): test_compare_ranges.cpp; a campaign
// compared with itself: test_compare_self.cpp.
#include <fmt/format.h>

#include <boost/test/unit_test.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>

#include "checks/checks.hpp"
#include "checks/compare_check.hpp"
#include "checks/regression_check.hpp"
#include "compare_runs.hpp"
#include "hostile_hdf5.hpp"
#include "process.hpp"
#include "sim/io/content_checksum.hpp"

namespace fs = std::filesystem;
using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

/// Three ensembles (two rates at N = 256, one at N = 1024) of each code: DIR with `dir`'s
/// samples, step and shift, REF with 16 samples on phi_step 0.0005 and a scaling-fit window
/// 0.83 ... 0.85.
struct Pair {
  StatsData dir, ref;
};

Pair make_pair(const EnsembleDesign& dir, std::uint64_t seed, double ref_jamming = NAN) {
  std::mt19937_64 rng(seed);
  Pair p;
  p.ref.fit_window_min = 0.83;
  p.ref.fit_window_max = 0.85;
  for (auto [n, rate] : {std::pair<std::int64_t, double>{256, -5}, {256, -6}, {1024, -5}}) {
    EnsembleDesign d = dir;
    d.n = n;
    d.log10_rate = rate;
    p.dir.ensembles.push_back(synthetic_ensemble(d, rng));
    EnsembleDesign r;
    r.n = n;
    r.log10_rate = rate;
    r.samples = 16;
    r.scatter = dir.scatter;
    r.first_id = 1000;  // other seeds: other sample numbers
    r.jamming_mean = ref_jamming;
    p.ref.ensembles.push_back(synthetic_ensemble(r, rng));
  }
  return p;
}

CheckOptions options() {
  CheckOptions o;
  o.permutations = 400;
  return o;
}

std::vector<Verdict> of(const std::vector<Verdict>& all, const std::string& check) {
  std::vector<Verdict> out;
  for (const auto& v : all)
    if (v.check == check) out.push_back(v);
  return out;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(equal_physics_on_other_seeds_samples_and_grids_never_fails) {
  // DIR: 10 samples on phi_step 0.0005 (REF's), 0.00025 (every other point shared), 0.0003
  // (every 0.0015 shared) and 0.00033 (incommensurate: nothing shared, interpolated); REF: 16
  // samples on 0.0005. 5% scatter per run.
  int passed = 0, judged = 0;
  for (double step : {0.0005, 0.00025, 0.0003, 0.00033}) {
    EnsembleDesign d;
    d.phi_step = step;
    d.samples = 10;
    const Pair p = make_pair(d, 11);
    const auto all = compare_check(p.dir, p.ref, options(), {});
    const auto pressure = of(all, "compare");
    BOOST_TEST_REQUIRE(pressure.size() == 6u);  // 3 ensembles, constant phi and constant Z
    for (const auto& v : pressure) {
      BOOST_TEST(v.status != "fail", step << " " << v.case_name << ": " << v.reason);
      BOOST_TEST(v.margin == 0.05);
      ++judged;
      passed += v.status == "pass";
      BOOST_TEST(v.values.count("n") == 1u);
      BOOST_TEST(v.values.count("phi_init") == 1u);
      BOOST_TEST(v.values.count("log10_rate") == 1u);
      BOOST_TEST(v.values.count("constant_z") == 1u);
      if (v.values.at("constant_z") == 1.0) continue;
      // The range is REF's fit window; the reason says so and states the grids.
      BOOST_TEST(has(v.reason, "REF's scaling-fit window"), v.reason);
      BOOST_TEST(v.values.at("range_min") >= 0.83 - 1e-12);
      BOOST_TEST(v.values.at("range_max") <= 0.85 + 1e-12);
      BOOST_TEST(has(v.reason, "DIR 10 samples, REF 16"), v.reason);
      if (step == 0.00033) {
        BOOST_TEST(v.values.at("interpolated") == 1.0);
        BOOST_TEST(has(v.reason,
                       "DIR's samples interpolated linearly onto REF's grid "
                       "(phi_step 0.00033 vs 0.0005"),
                   v.reason);
      } else {
        BOOST_TEST(v.values.at("interpolated") == 0.0);
        BOOST_TEST(has(v.reason, "grid values both grids share in the range"), v.reason);
        BOOST_TEST(has(v.reason, fmt::format("phi_step {:.3g} vs 0.0005", step)), v.reason);
      }
    }
    // Everything matched, no fits in either file: said once for each fit part.
    BOOST_TEST(of(all, "compare_fit").size() == 1u);
    BOOST_TEST(has(of(all, "compare_fit")[0].reason, "nor REF's"));
  }
  BOOST_TEST_MESSAGE("equal physics: " << passed << " of " << judged << " pass, none fail");
  BOOST_TEST(passed >= judged / 2);  // the check is not dead: most verdicts decide
}

// 15% at a 5% margin: D's detection band here is about 5%, so the data exclude every effect at
// or below the margin (a fail needs that; 10% left the margin inside the band).
BOOST_AUTO_TEST_CASE(a_planted_fifteen_percent_pressure_difference_fails) {
  for (double step : {0.0005, 0.00033}) {
    EnsembleDesign d;
    d.phi_step = step;
    d.shift = 0.15;
    const Pair p = make_pair(d, 12);
    for (const auto& v : of(compare_check(p.dir, p.ref, options(), {}), "compare")) {
      BOOST_TEST(v.status == "fail", step << " " << v.case_name << ": " << v.reason);
      // Delta p/p relative to REF: about +0.15.
      BOOST_TEST(std::abs(v.values.at("difference") - 0.15) < 0.04, v.reason);
    }
  }
}

BOOST_AUTO_TEST_CASE(the_range_given_or_else_past_the_transients) {
  EnsembleDesign d;
  Pair p = make_pair(d, 13);
  CheckOptions o = options();
  o.phi_min = 0.835;
  o.phi_max = 0.845;
  for (const auto& v : of(compare_check(p.dir, p.ref, o, {}), "compare")) {
    if (v.values.at("constant_z") == 1.0) continue;
    BOOST_TEST(has(v.reason, "the range given (--phi-min, --phi-max)"), v.reason);
    BOOST_TEST(v.values.at("range_min") == 0.835, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(v.values.at("range_max") == 0.845, boost::test_tools::tolerance(1e-9));
  }
  // No fit in REF: from where both are past their compression transients.
  p.ref.fit_window_min.reset();
  p.ref.fit_window_max.reset();
  for (auto& e : p.dir.ensembles) e.compressed_from_phi = 0.81;
  for (auto& e : p.ref.ensembles) e.compressed_from_phi = 0.812;
  for (const auto& v : of(compare_check(p.dir, p.ref, options(), {}), "compare")) {
    if (v.values.at("constant_z") == 1.0) continue;
    BOOST_TEST(has(v.reason, "no scaling fit in REF's stats.h5"), v.reason);
    BOOST_TEST(has(v.reason, "from where the compression sets both sets' pressure"), v.reason);
    BOOST_TEST(v.values.at("range_min") == 0.812, boost::test_tools::tolerance(1e-9));
  }
  // A narrow range in which 0.0003 and 0.0005 share fewer than two values: interpolated.
  d.phi_step = 0.0003;
  p = make_pair(d, 14);
  o.phi_min = 0.8405;
  o.phi_max = 0.8425;
  for (const auto& v : of(compare_check(p.dir, p.ref, o, {}), "compare")) {
    if (v.values.at("constant_z") == 1.0) continue;
    BOOST_TEST(v.values.at("interpolated") == 1.0, v.reason);
    BOOST_TEST(v.values.at("shared_points") <= 1.0);
    BOOST_TEST(has(v.reason, "phi_step 0.0003 vs 0.0005"), v.reason);
  }
}

BOOST_AUTO_TEST_CASE(a_jamming_point_shift_of_0_01_fails_compare_jamming) {
  EnsembleDesign d;
  d.jamming_mean = 0.8415;
  const Pair same = make_pair(d, 15, 0.8415);
  const auto equal = of(compare_check(same.dir, same.ref, options(), {}), "compare_jamming");
  BOOST_TEST_REQUIRE(equal.size() == 3u);
  for (const auto& v : equal) {
    BOOST_TEST(v.status != "fail", v.case_name << ": " << v.reason);
    BOOST_TEST(v.margin == 0.005);
    BOOST_TEST(has(v.reason, "spread of phi_Ji (standard deviation): DIR "), v.reason);
    BOOST_TEST(v.values.at("spread_dir") > 0.001);
    BOOST_TEST(v.values.at("spread_ref") < 0.006);
  }
  d.jamming_mean = 0.8515;
  const Pair shifted = make_pair(d, 16, 0.8415);
  for (const auto& v :
       of(compare_check(shifted.dir, shifted.ref, options(), {}), "compare_jamming")) {
    BOOST_TEST(v.status == "fail", v.case_name << ": " << v.reason);
    BOOST_TEST(std::abs(v.values.at("difference") - 0.01) < 0.004, v.reason);
  }
  // Only one side looked for jamming points: said, not dropped.
  const Pair one = make_pair(d, 17);
  const auto lone = of(compare_check(one.dir, one.ref, options(), {}), "compare_jamming");
  BOOST_TEST_REQUIRE(lone.size() == 3u);
  BOOST_TEST(lone[0].status == "inconclusive");
  BOOST_TEST(has(lone[0].reason, "only DIR carries jamming points"), lone[0].reason);
}

BOOST_AUTO_TEST_CASE(ensembles_without_a_partner_are_named) {
  EnsembleDesign d;
  Pair p = make_pair(d, 18);
  p.dir.ensembles[0].n = 512;                // no n512 in REF
  p.ref.ensembles[1].log10_rate = -7;        // no rate 1e-7 in DIR
  p.dir.ensembles[2].phi_init = 0.4 + 4e-7;  // within 1e-6: still REF's partner
  const auto all = compare_check(p.dir, p.ref, options(), {});
  const Verdict* unmatched = nullptr;
  int pressure = 0;
  for (const auto& v : all) {
    if (v.case_name == "ensembles without a partner")
      unmatched = &v;
    else if (v.check == "compare")
      ++pressure;
  }
  BOOST_TEST_REQUIRE(unmatched != nullptr);
  BOOST_TEST(unmatched->status == "inconclusive");
  BOOST_TEST(has(unmatched->reason,
                 "in DIR only: n512 phi_init 0.4 rate 1e-5, n256 phi_init 0.4 "
                 "rate 1e-6"),
             unmatched->reason);
  BOOST_TEST(has(unmatched->reason,
                 "in REF only: n256 phi_init 0.4 rate 1e-5, n256 phi_init 0.4 "
                 "rate 1e-7"),
             unmatched->reason);
  BOOST_TEST(pressure == 2);  // the one pair left, at constant phi and Z
  // phi_init 0.401 is another start.
  p = make_pair(d, 19);
  p.dir.ensembles[0].phi_init = 0.401;
  for (const auto& v : compare_check(p.dir, p.ref, options(), {}))
    if (v.case_name == "ensembles without a partner")
      BOOST_TEST(has(v.reason, "in DIR only: n256 phi_init 0.401 rate 1e-5"), v.reason);
  // Another dimension: nothing compared, said.
  p.ref.dim = 3;
  const auto dims = compare_check(p.dir, p.ref, options(), {});
  BOOST_TEST_REQUIRE(dims.size() == 1u);
  BOOST_TEST(has(dims[0].reason, "DIR is 2D, REF 3D"), dims[0].reason);
}

BOOST_AUTO_TEST_CASE(fitted_parameters_compared_per_size_and_start) {
  auto family = [](std::int64_t n, double phi_init, double beta, double phi_j) {
    FamilyParameters f;
    f.n = n;
    f.phi_init = phi_init;
    f.beta = beta, f.beta_err = 0.01 * beta;
    f.y = 1.05, f.y_err = 0.0105;
    f.phi_j = phi_j, f.phi_j_err = 0.0001;
    f.samples = 10;
    return f;
  };
  StatsData dir, ref;
  dir.families = {family(256, 0.4, 2.8, 0.8415), family(1024, 0.4, 3.64, 0.8415),
                  family(256, 0.6, 2.8, 0.8515), family(512, 0.4, 2.8, 0.8415)};
  ref.families = {family(256, 0.4, 2.8, 0.8415), family(1024, 0.4, 2.8, 0.8415),
                  family(256, 0.6, 2.8, 0.8415), family(2048, 0.4, 2.8, 0.8415)};
  dir.families[0].phi_init = 0.4 + 5e-7;  // the same start, as another code writes it
  const auto all = compare_check(dir, ref, options(), {});
  auto find = [&](const std::string& check, const std::string& part) -> const Verdict& {
    for (const auto& v : all)
      if (v.check == check && has(v.case_name, part)) return v;
    throw std::runtime_error("no verdict " + check + " " + part);
  };
  BOOST_TEST(find("compare_fit", "n256 phi_init 0.4:").status == "pass");
  BOOST_TEST(find("compare_fit_phi_j", "n256 phi_init 0.4:").status == "pass");
  // beta 30% above REF's (relative to REF: +0.30): fails, naming beta.
  const Verdict& beta = find("compare_fit", "n1024 phi_init 0.4");
  BOOST_TEST(beta.status == "fail", beta.reason);
  BOOST_TEST(has(beta.reason, "differ: beta"), beta.reason);
  BOOST_TEST(has(beta.reason, "Delta +30%"), beta.reason);
  BOOST_TEST(beta.margin == 0.10);
  // phi_J 0.01 apart: its own part fails.
  BOOST_TEST(find("compare_fit_phi_j", "n256 phi_init 0.6").status == "fail");
  BOOST_TEST(find("compare_fit_phi_j", "n256 phi_init 0.6").margin == 0.002);
  const Verdict& lone = find("compare_fit", "fits without a partner");
  BOOST_TEST(has(lone.reason, "fitted in DIR only: n512 phi_init 0.4"), lone.reason);
  BOOST_TEST(has(lone.reason, "fitted in REF only: n2048 phi_init 0.4"), lone.reason);
}

BOOST_AUTO_TEST_CASE(grids_are_matched_on_shared_values_or_interpolated) {
  // A linear curve: interpolation onto REF's grid is exact.
  const auto dir_grid = step_grid(0.80, 0.86, 0.00033), ref_grid = step_grid(0.80, 0.86, 0.0005);
  auto line = [](const std::vector<double>& g, double slope) {
    std::vector<double> row;
    for (double x : g) row.push_back(1 + slope * (x - 0.8));
    return row;
  };
  const GridMatch m = match_grids(dir_grid, {line(dir_grid, 3), line(dir_grid, 5)}, ref_grid,
                                  {line(ref_grid, 3)}, 0.83, 0.85);
  BOOST_TEST(m.interpolated);
  BOOST_TEST(m.shared <= 1u);
  BOOST_TEST(m.step_dir == 0.00033, boost::test_tools::tolerance(1e-9));
  BOOST_TEST(m.step_ref == 0.0005, boost::test_tools::tolerance(1e-9));
  BOOST_TEST_REQUIRE(m.aligned.grid.size() == 41u);  // 0.830, 0.8305, ..., 0.850
  for (std::size_t k = 0; k < m.aligned.grid.size(); ++k) {
    BOOST_TEST(m.aligned.a[0][k] == m.aligned.b[0][k], boost::test_tools::tolerance(1e-12));
    BOOST_TEST(m.aligned.a[1][k] == 1 + 5 * (m.aligned.grid[k] - 0.8),
               boost::test_tools::tolerance(1e-12));
  }
  // Never extrapolated: REF's values beyond DIR's grid are left out.
  const auto short_grid = step_grid(0.80, 0.84, 0.00033);
  const GridMatch cut =
      match_grids(short_grid, {line(short_grid, 3)}, ref_grid, {line(ref_grid, 3)}, 0.83, 0.85);
  BOOST_TEST(cut.aligned.grid.back() <= short_grid.back());
  // Multiples of a step: the shared values.
  const auto fine = step_grid(0.80, 0.86, 0.00025);
  const GridMatch shared =
      match_grids(fine, {line(fine, 3)}, ref_grid, {line(ref_grid, 3)}, 0.83, 0.85);
  BOOST_TEST(!shared.interpolated);
  BOOST_TEST(shared.shared == 41u);
}

/// Every per-sample pressure of a stats.h5 multiplied by `factor` (the units attribute goes).
void scale_pressures(const fs::path& file, double factor) {
  struct Edit {
    std::string name;
    std::vector<double> values;
    hsize_t rows;
  };
  std::vector<Edit> edits;
  {
    const auto f = jam::h5::File::open_read(file.string());
    for (const auto& e : f.list_group("ensembles")) {
      for (const char* average : {"constant_phi", "constant_z"}) {
        const std::string g = "ensembles/" + e + "/" + average;
        if (!f.has_dataset(g)) continue;
        Edit x{g + "/pressure_samples", f.read_dataset(g + "/pressure_samples"),
               f.read_dataset(g + "/sample_ids").size()};
        for (double& p : x.values) p *= factor;
        edits.push_back(std::move(x));
      }
    }
  }
  {
    jam::test::Editor editor(file);
    for (const auto& x : edits) {
      std::string bytes(x.values.size() * sizeof(double), '\0');
      std::memcpy(bytes.data(), x.values.data(), bytes.size());
      editor.set_dataset(x.name, jam::test::ValueClass::kFloat,
                         {x.rows, x.values.size() / x.rows}, bytes);
    }
  }
  // The edit is the test's own: seal the file again (as `jam stats` would have written it), or
  // jam check refuses a stats.h5 changed since it was written.
  std::string text;
  {
    const auto f = jam::h5::File::open_read(file.string());
    text = jam::checksum_text(jam::content_checksum(f, {"checksum"}));
  }
  jam::test::Editor(file).set_text(".", "checksum", text);
}

BOOST_AUTO_TEST_CASE(jam_check_compare_runs_through_the_baseline_path) {
  // The stored 3D reproduction against a copy whose pressures are 0.2% higher (a copy of the
  // same file is refused: a campaign compared with itself, test_compare_self.cpp): every
  // verdict of the four parts, none fails, written to DIR/checks-compare.*; without --against
  // it refuses in one line.
  const fs::path root = fs::temp_directory_path() / "jam-test-compare-check";
  fs::remove_all(root);
  for (const char* d : {"dir", "ref"}) {
    fs::create_directories(root / d);
    fs::copy_file(fs::path(JAM_SOURCE_DIR) / "reference/results/reduced-3d/stats.h5",
                  root / d / "stats.h5");
  }
  scale_pressures(root / "ref" / "stats.h5", 1.002);
  const auto out = jam::test::run_jam_logged(
      root / "log.txt", "check compare " + (root / "dir").string() + " --against " +
                            (root / "ref").string() + " --permutations 200");
  BOOST_TEST((out.status == 0 || out.status == 3), out.output);
  const auto json = nlohmann::json::parse(std::ifstream(root / "dir" / "checks-compare.json"));
  std::set<std::string> checks;
  for (const auto& v : json["verdicts"]) {
    checks.insert(v["check"].get<std::string>());
    BOOST_TEST(v["status"] != "fail", v["case"] << ": " << v["reason"]);
  }
  BOOST_TEST(checks.count("compare") == 1u);
  BOOST_TEST(checks.count("compare_jamming") == 1u);
  BOOST_TEST(checks.count("compare_fit") == 1u);
  BOOST_TEST(checks.count("compare_fit_phi_j") == 1u);
  BOOST_TEST(has(out.output, "compare: "), out.output);  // the verdict table's heading
  const auto refused =
      jam::test::run_jam_stderr(root / "err.txt", "check compare " + (root / "dir").string());
  BOOST_TEST(refused.status == 2);
  BOOST_TEST(has(refused.output, "compare: --against BASELINE_DIR is required"), refused.output);
}
