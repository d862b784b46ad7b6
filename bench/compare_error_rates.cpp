// The error rates of the compare check (checks/compare_check.cpp), measured once on synthetic
// pairs of campaigns (tests/compare_runs.hpp): DIR and REF of the same physics from other
// seeds, 10 against 10 samples, per-run relative scatter 5-10% correlated along phi (0.9 per
// 0.001), three ensembles each (constant phi and constant Z: six comparisons sharing alpha
// 0.05), REF's fit window 0.83 ... 0.85, margin 0.05. For each set-up, `repeats` pairs with
// nothing planted (the false-alarm rate: a `fail` anywhere in the check; and how many verdicts
// pass) and `repeats` with DIR's pressure 1.2 x the margin above REF's (Delta p/p = 0.06: the
// false-pass rate, per verdict). Not a test: docs/statistics-and-checks.md#compare keeps what
// it printed. Built on request:
//   cmake --build BUILD --target compare_error_rates && BUILD/tests/compare_error_rates [repeats]
//   [set-up index]
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "checks/checks.hpp"
#include "checks/regression_check.hpp"
#include "compare_runs.hpp"

using namespace jam::checks;
using namespace jam::checks::testing;

namespace {

struct SetUp {
  std::string name;
  double scatter, dir_step;
  int ensembles;  // 3: the check as used; 1 without constant Z: one comparison at alpha itself
};

struct Pair {
  StatsData dir, ref;
};

Pair make_pair(const SetUp& s, double shift, std::mt19937_64& rng) {
  Pair p;
  p.ref.fit_window_min = 0.83;
  p.ref.fit_window_max = 0.85;
  const std::vector<std::pair<std::int64_t, double>> which = {{256, -5}, {256, -6}, {1024, -5}};
  for (int k = 0; k < s.ensembles; ++k) {
    EnsembleDesign d;
    d.n = which[k].first;
    d.log10_rate = which[k].second;
    d.samples = 10;
    d.scatter = s.scatter;
    d.phi_step = s.dir_step;
    d.shift = shift;
    p.dir.ensembles.push_back(synthetic_ensemble(d, rng));
    d.phi_step = 0.0005;
    d.shift = 0.0;
    d.first_id = 1000;
    p.ref.ensembles.push_back(synthetic_ensemble(d, rng));
    if (s.ensembles == 1) {
      p.dir.ensembles.back().pressure_at_z.clear();
      p.ref.ensembles.back().pressure_at_z.clear();
    }
  }
  return p;
}

struct Counts {
  int repeats_failing = 0, verdicts = 0, fail = 0, pass = 0, detected = 0;
};

Counts run(const SetUp& s, double shift, int repeats, std::uint64_t seed) {
  Counts c;
  CheckOptions o;  // alpha 0.05, margin 0.05, the default permutations
  for (int r = 0; r < repeats; ++r) {
    std::mt19937_64 rng(seed + static_cast<std::uint64_t>(r));
    const Pair p = make_pair(s, shift, rng);
    bool any_fail = false;
    for (const auto& v : compare_check(p.dir, p.ref, o, {})) {
      if (v.check != "compare" || !v.values.count("difference")) continue;
      ++c.verdicts;
      c.fail += v.status == "fail";
      c.pass += v.status == "pass";
      c.detected += v.statistic > v.threshold;
      any_fail = any_fail || v.status == "fail";
    }
    c.repeats_failing += any_fail;
  }
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 300;
  const std::vector<SetUp> setups = {
      {"one comparison (constant phi), 7.5% scatter, same grid", 0.075, 0.0005, 1},
      {"3 ensembles x (phi, Z), 5% scatter, same grid (0.0005)", 0.05, 0.0005, 3},
      {"3 ensembles x (phi, Z), 10% scatter, same grid (0.0005)", 0.10, 0.0005, 3},
      {"3 ensembles x (phi, Z), 7.5% scatter, DIR 0.00025 vs REF 0.0005", 0.075, 0.00025, 3},
      {"3 ensembles x (phi, Z), 7.5% scatter, DIR 0.00033 interpolated", 0.075, 0.00033, 3},
  };
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;  // one set-up by its index
  fmt::print("compare: 10 vs 10 samples, alpha 0.05, margin 0.05, {} repeats per row\n", repeats);
  for (std::size_t k = 0; k < setups.size(); ++k) {
    if (only >= 0 && static_cast<std::size_t>(only) != k) continue;
    const SetUp& s = setups[k];
    const auto started = std::chrono::steady_clock::now();
    const Counts null = run(s, 0.0, repeats, 100000);
    const Counts effect = run(s, 1.2 * 0.05, repeats, 200000);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    fmt::print(
        "{}\n  nothing planted: check fails in {}/{} = {:.3f} of repeats; verdicts: {} "
        "detected ({:.3f}), {} pass ({:.3f}) of {}\n"
        "  Delta p/p = 0.06 (1.2 M): verdicts pass {}/{} = {:.3f}, fail {:.3f}, inconclusive "
        "{:.3f}  [{:.0f} s]\n",
        s.name, null.repeats_failing, repeats, double(null.repeats_failing) / repeats,
        null.detected, double(null.detected) / null.verdicts, null.pass,
        double(null.pass) / null.verdicts, null.verdicts, effect.pass, effect.verdicts,
        double(effect.pass) / effect.verdicts, double(effect.fail) / effect.verdicts,
        double(effect.verdicts - effect.pass - effect.fail) / effect.verdicts, seconds);
    std::fflush(stdout);
  }
  return 0;
}
