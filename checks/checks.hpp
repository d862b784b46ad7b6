#pragma once
// The statistical checks of `jam check NAME DIR`: each turns the per-sample tables of
// DIR/stats.h5 into verdicts (checks/verdict.hpp). Which checks there are, and their default
// margins: checks/check_registry.hpp.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "checks/regions.hpp"
#include "checks/relative_difference.hpp"
#include "checks/stats_data.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

/// Names a run set: an ensemble of stats.h5 by size, phi_init and log10 rate
/// (written "n=1024,phi_init=0.6,rate=-4"; fields left out match anything).
struct RunSetSelector {
  std::optional<std::int64_t> n;
  std::optional<double> phi_init, log10_rate;
  static RunSetSelector parse(const std::string& text);  // throws naming the bad field
  bool matches(const EnsembleTables& e) const;
};

/// The default margin M of a registered check (its registry entry, checks/check_registry.hpp,
/// says what it measures and why it is what it is). Throws for an unregistered name.
double default_margin(const std::string& check);

struct CheckOptions {
  double alpha = 0.05;  // false-alarm rate of a whole check (Bonferroni over its comparisons)
  int permutations = 2000;
  // The packing range the pressure checks pool over (checks/pooled_verdict.hpp; default: the
  // campaign's scaling-fit window).
  std::optional<double> phi_min, phi_max;
  // Where the regions below, at and above jamming lie (checks/regions.hpp): phi_J when given
  // (else the fit's, else <phi_Ji>), and the regions' offsets from it.
  std::optional<double> phi_j;
  RegionOffsets regions;
  std::optional<RunSetSelector> set_a, set_b;  // finite-size check of two named run sets
  std::map<std::string, double> margins;       // per check; default_margin() otherwise
  // The alpha the samples estimates aim at (until-decided: the next look's); alpha when unset.
  std::optional<double> estimate_alpha;
  /// A check's levels scaled to estimate_alpha, for its samples estimates.
  Levels for_estimate(Levels judged) const {
    const double f = estimate_alpha ? *estimate_alpha / alpha : 1.0;
    return {judged.detect * f, judged.pass * f};
  }
  double margin(const std::string& check) const {
    const auto it = margins.find(check);
    return it != margins.end() ? it->second : default_margin(check);
  }
};

std::vector<Verdict> finite_size_check(const StatsData& d, const CheckOptions& o);
std::vector<Verdict> sample_pairs_check(const StatsData& d, const CheckOptions& o);
std::vector<Verdict> phi_init_check(const StatsData& d, const CheckOptions& o);
/// zeta = p / rate below phi_J at the two slowest rates (zeta_check.cpp).
std::vector<Verdict> zeta_check(const StatsData& d, const CheckOptions& o);
/// The fitted phi_J, beta and y of each size and start (fit_parameters_check.cpp).
std::vector<Verdict> fit_parameters_check(const StatsData& d, const CheckOptions& o);

struct RegressionOptions;
/// Each chained rate against the same samples compressed without chaining (chain_check.cpp).
std::vector<Verdict> chain_check(const StatsData& chained, const StatsData& control,
                                 const CheckOptions& o, const RegressionOptions&);
/// A campaign's pressures against the same runs redone at a stricter integrator setting, over
/// the same samples (convergence_check.cpp).
std::vector<Verdict> convergence_check(const StatsData& campaign, const StatsData& converged,
                                       const CheckOptions& o, const RegressionOptions&);
/// Two campaigns of the same model, ensemble by ensemble: DIR (e.g. another simulator's runs)
/// against REF (the reference simulator's), whatever their samples, seeds and grids; verdicts
/// compare, compare_jamming, compare_fit and compare_fit_phi_j (compare_check.cpp).
std::vector<Verdict> compare_check(const StatsData& dir, const StatsData& ref,
                                   const CheckOptions& o, const RegressionOptions&);

/// Runs one statistical check by name, or "all": the statistical members of `all` (the checks
/// of other kinds: run_checks, checks/run_checks.hpp).
std::vector<Verdict> run_check(const std::string& name, const StatsData& d, const CheckOptions& o);

}  // namespace jam::checks
