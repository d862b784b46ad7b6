// What physicists compare: the fitted scaling parameters of each size and each start
// (stats.h5 fit/families: every (N, phi_init) fitted at the representative fit's window,
// rate_max and order, with jackknife errors). Sizes: the smallest against the largest at each
// phi_init; starts: each phi_init against the lowest at each N. Two verdicts per comparison:
//   fit_parameters  the exponents beta and y, relative differences 2 (a - b) / (a + b)
//                   against the margin (default 10%); the reason names those that differ;
//   fit_phi_j       phi_J, a difference in packing (default margin 0.002).
// Each parameter's difference is t = |Delta| / sigma, sigma from both jackknife errors, judged
// with Student's t at (samples - 1) degrees of freedom (the jackknife's): detected beyond the
// (1 - detect / 2) quantile, its share of alpha over the check's comparisons (Bonferroni);
// effects beyond |Delta| + t_(1 - alpha) sigma excluded (two one-sided tests at alpha): the
// rule of checks/parameter_difference.hpp, which the compare check shares.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "checks/checks.hpp"
#include "checks/margin.hpp"
#include "checks/parameter_difference.hpp"
#include "stats/campaign_stats.hpp"

namespace jam::checks {
namespace {

double relative(double a, double b) {
  return 2 * (a - b) / (a + b);
}
double relative_sigma(double a, double ea, double b, double eb) {
  return 4 / ((a + b) * (a + b)) * std::sqrt(b * b * ea * ea + a * a * eb * eb);
}

/// "no scaling fit: fewer than 3 rates (...)" when the campaign's design cannot fit (`jam
/// stats` then attempts none, stats/campaign_stats.hpp); "" otherwise.
std::string fewer_rates(const StatsData& d) {
  std::set<double> rates;
  for (const auto& e : d.ensembles) rates.insert(e.log10_rate);
  if (d.ensembles.empty() || rates.size() >= stats::kFitRatesMin) return "";
  std::string listed;
  for (auto it = rates.rbegin(); it != rates.rend(); ++it)
    listed += fmt::format("{}1e{:g}", listed.empty() ? "" : ", ", *it);
  return fmt::format(
      "no scaling fit: fewer than {} rates (the campaign has {}: {}), so no per-size fits to "
      "compare; a scaling fit needs at least {} (with 2, phi_J and q trade off)",
      stats::kFitRatesMin, rates.size(), listed, stats::kFitRatesMin);
}

}  // namespace

std::vector<Verdict> fit_parameters_check(const StatsData& d, const CheckOptions& o) {
  // Nothing to compare: one verdict of each (the check and its part) says why.
  auto neither = [](const std::string& why) {
    return std::vector<Verdict>{inconclusive("fit_parameters", "all", why),
                                inconclusive("fit_phi_j", "all", why)};
  };
  if (const std::string few = fewer_rates(d); !few.empty()) return neither(few);
  if (d.families.empty()) {
    return neither(
        "stats.h5 has no per-size fits (fit/families): no representative scaling fit, or "
        "written by an older jam (rerun `jam stats`)");
  }
  std::map<std::pair<std::int64_t, double>, const FamilyParameters*> by;
  std::set<std::int64_t> sizes;
  std::set<double> starts;
  for (const auto& f : d.families) {
    by[{f.n, f.phi_init}] = &f;
    sizes.insert(f.n);
    starts.insert(f.phi_init);
  }
  struct Pair {
    const FamilyParameters *a, *b;
    std::string what;
  };
  std::vector<Pair> pairs;
  if (sizes.size() >= 2)
    for (double phi : starts) {
      const auto a = by.find({*sizes.begin(), phi}), b = by.find({*sizes.rbegin(), phi});
      if (a != by.end() && b != by.end())
        pairs.push_back(
            {a->second, b->second,
             fmt::format("n{} vs n{}, phi_init {:g}", *sizes.begin(), *sizes.rbegin(), phi)});
    }
  if (starts.size() >= 2)
    for (auto n : sizes)
      for (double phi : starts) {
        if (phi == *starts.begin()) continue;
        const auto a = by.find({n, phi}), b = by.find({n, *starts.begin()});
        if (a != by.end() && b != by.end())
          pairs.push_back({a->second, b->second,
                           fmt::format("n{}: phi_init {:g} vs {:g}", n, phi, *starts.begin())});
      }
  if (pairs.empty()) return neither("a single size and a single phi_init: nothing to compare");
  const double detect = o.alpha / static_cast<double>(pairs.size());
  std::vector<Verdict> out;
  for (const auto& p : pairs) {
    std::map<std::string, double> values = {{"n_a", static_cast<double>(p.a->n)},
                                            {"n_b", static_cast<double>(p.b->n)},
                                            {"phi_init_a", p.a->phi_init},
                                            {"phi_init_b", p.b->phi_init}};
    if (!p.a->failure.empty() || !p.b->failure.empty()) {
      const std::string why = fmt::format(
          "no fit for {}",
          !p.a->failure.empty()
              ? fmt::format("n{} phi_init {:g}: {}", p.a->n, p.a->phi_init, p.a->failure)
              : fmt::format("n{} phi_init {:g}: {}", p.b->n, p.b->phi_init, p.b->failure));
      out.push_back(inconclusive("fit_parameters", "exponents, " + p.what, why));
      out.push_back(inconclusive("fit_phi_j", "phi_J, " + p.what, why));
      continue;
    }
    // A fit its own quality test calls poor (the form does not describe its points, or its
    // errors exceed half the exponents) estimates nothing to compare: neither a difference
    // "surely beyond the margin" nor an agreement can rest on it.
    if (p.a->quality != "ok" || p.b->quality != "ok") {
      const FamilyParameters& poor = p.a->quality != "ok" ? *p.a : *p.b;
      const std::string why = fmt::format(
          "the fit of n{} phi_init {:g} is of quality {} ({}): its parameters are no estimate "
          "of the scaling form's",
          poor.n, poor.phi_init, poor.quality, poor.quality_reason);
      out.push_back(inconclusive("fit_parameters", "exponents, " + p.what, why));
      out.push_back(inconclusive("fit_phi_j", "phi_J, " + p.what, why));
      continue;
    }
    const std::int64_t samples = std::min(p.a->samples, p.b->samples);
    Verdict exponents =
        judge_parameters("fit_parameters", "exponents, " + p.what,
                         {{"beta", p.a->beta, p.b->beta, relative(p.a->beta, p.b->beta),
                           relative_sigma(p.a->beta, p.a->beta_err, p.b->beta, p.b->beta_err)},
                          {"y", p.a->y, p.b->y, relative(p.a->y, p.b->y),
                           relative_sigma(p.a->y, p.a->y_err, p.b->y, p.b->y_err)}},
                         samples, detect, o.alpha, o.margin("fit_parameters"));
    Verdict phi_j = judge_parameters("fit_phi_j", "phi_J, " + p.what,
                                     {{"phi_J", p.a->phi_j, p.b->phi_j, p.a->phi_j - p.b->phi_j,
                                       std::hypot(p.a->phi_j_err, p.b->phi_j_err)}},
                                     samples, detect, o.alpha, o.margin("fit_phi_j"));
    exponents.values = values;
    phi_j.values = values;
    out.push_back(std::move(exponents));
    out.push_back(std::move(phi_j));
  }
  return out;
}

}  // namespace jam::checks
