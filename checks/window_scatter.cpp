#include "checks/window_scatter.hpp"

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

namespace jam::checks {

WindowScatter window_scatter(const Aligned& al, const std::vector<std::size_t>& points,
                             const std::vector<double>& weight) {
  // pbar_k: the mean of both sets' means, the denominator of Delta_k (relative_difference.hpp).
  std::vector<double> mean(points.size(), 0.0);
  for (const auto* set : {&al.a, &al.b}) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      double m = 0.0;
      for (const auto& run : *set) m += run[points[i]];
      mean[i] += 0.5 * m / static_cast<double>(set->size());
    }
  }
  auto scatter = [&](const std::vector<std::vector<double>>& set) {
    if (set.size() < 2) return static_cast<double>(NAN);
    std::vector<double> u;
    for (const auto& run : set) {
      double x = 0.0;
      for (std::size_t i = 0; i < points.size(); ++i) x += weight[i] * run[points[i]] / mean[i];
      u.push_back(x);
    }
    double m = 0.0, ss = 0.0;
    for (double x : u) m += x / static_cast<double>(u.size());
    for (double x : u) ss += (x - m) * (x - m);
    return std::sqrt(ss / static_cast<double>(u.size() - 1));
  };
  return {scatter(al.a), scatter(al.b)};
}

SamplesNeeded samples_for_sigma(double target, double s_a, double s_b, double cost_a, double cost_b,
                                double present_a, double present_b) {
  SamplesNeeded out;
  if (!std::isfinite(s_a) || !std::isfinite(s_b) || s_a + s_b <= 0 || !(target > 0)) return out;
  const double t2 = target * target;
  out.equal = std::max(std::ceil((s_a * s_a + s_b * s_b) / t2), std::max(present_a, present_b) + 1);
  // Cheapest split: minimise c_a n_a + c_b n_b at s_a^2/n_a + s_b^2/n_b = target^2, so
  // n proportional to s / sqrt(c); a set already beyond its share keeps its samples and the
  // other makes up the rest.
  const double ra = std::sqrt(cost_a), rb = std::sqrt(cost_b);
  double na = s_a * (s_a * ra + s_b * rb) / (ra * t2), nb = s_b * (s_a * ra + s_b * rb) / (rb * t2);
  if (na < present_a) {
    na = present_a;
    const double left = t2 - s_a * s_a / na;
    nb = left > 0 ? s_b * s_b / left : INFINITY;
  } else if (nb < present_b) {
    nb = present_b;
    const double left = t2 - s_b * s_b / nb;
    na = left > 0 ? s_a * s_a / left : INFINITY;
  }
  out.a = std::ceil(std::max(na, present_a));
  out.b = std::ceil(std::max(nb, present_b));
  if (out.a <= present_a && out.b <= present_b) out.a = present_a + 1, out.b = present_b + 1;
  return out;
}

SamplesNeeded samples_needed(double difference, double s_a, double s_b, double cost_a,
                             double cost_b, double present_a, double present_b, Levels levels,
                             double margin) {
  if (!std::isfinite(s_a) || !std::isfinite(s_b)) return {};
  const double z_pass = gsl_cdf_ugaussian_Qinv(levels.pass),
               z_detect = gsl_cdf_ugaussian_Qinv(levels.detect),
               z_power = gsl_cdf_ugaussian_Qinv(1 - kEstimatePower);
  // The sigma_D at which a verdict decides with probability kEstimatePower when the true
  // difference is delta: pass when |D| + z_pass sigma <= M, fail when |D| - z_detect sigma > M
  // (one-sided at the detection level, margin.hpp); whichever route allows the larger sigma
  // (the fewer samples).
  auto to_fail = [&](double delta) {
    return delta > margin ? (delta - margin) / (z_detect + z_power) : 0.0;
  };
  auto to_pass = [&](double delta) {
    return delta < margin ? (margin - delta) / (z_pass + z_power) : 0.0;
  };
  // The observed D is uncertain by sigma_D now, and near the margin the sigma that decides
  // changes fast with it: the estimate takes the median over 21 quantiles of delta ~
  // N(D, sigma_D now) rather than D itself (which made it jump between resamples).
  const double now = std::sqrt(s_a * s_a / present_a + s_b * s_b / present_b);
  std::vector<double> target;
  for (int i = 0; i < 21; ++i) {
    const double delta = std::abs(difference + now * gsl_cdf_ugaussian_Pinv((i + 0.5) / 21.0));
    target.push_back(std::max(to_fail(delta), to_pass(delta)));
  }
  std::nth_element(target.begin(), target.begin() + 10, target.end());
  SamplesNeeded n = samples_for_sigma(target[10], s_a, s_b, cost_a, cost_b, present_a, present_b);
  if (!std::isfinite(n.equal)) return n;
  // Permutations of whole runs reach a p-value of 2 / C(n_a + n_b, n_a) at best: the route's
  // level (detection; the band at twice the pass level) must be reachable.
  const double d = std::abs(difference);
  const double level = to_fail(d) >= to_pass(d) ? 2 * levels.detect : 2 * levels.pass;
  auto reachable = [level](double a, double b) {
    return std::log(2.0 / level) <=
           std::lgamma(a + b + 1) - std::lgamma(a + 1) - std::lgamma(b + 1);
  };
  while (!reachable(n.equal, n.equal)) n.equal += 1;
  while (!reachable(n.a, n.b)) (cost_a <= cost_b ? n.a : n.b) += 1;
  return n;
}

namespace {

double value_of(const Verdict& v, const char* key) {
  const auto it = v.values.find(key);
  return it == v.values.end() ? NAN : it->second;
}

/// ln s^2 at `rate`, fitted linear in log10 rate over the series' points within one decade,
/// each weighted by its degrees of freedom; a single point is its own estimate.
double pooled_scatter(const std::vector<std::pair<double, std::pair<double, double>>>& points,
                      double rate) {
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& [x, sd] : points) {
    const auto [s, dof] = sd;
    if (std::abs(x - rate) > 1.0 + 1e-9 || !(s > 0) || !(dof > 0)) continue;
    const double y = std::log(s * s), dx = x - rate;
    sw += dof, sx += dof * dx, sy += dof * y, sxx += dof * dx * dx, sxy += dof * dx * y;
  }
  if (sw <= 0) return NAN;
  const double det = sw * sxx - sx * sx;
  // The intercept at dx = 0; the mean when the rates do not spread (one rate).
  const double y0 = det > 1e-12 * sw * sw ? (sxx * sy - sx * sxy) / det : sy / sw;
  return std::sqrt(std::exp(y0));
}

}  // namespace

std::string samples_words(const SamplesNeeded& n, const std::string& name_a,
                          const std::string& name_b, bool pooled) {
  if (!std::isfinite(n.equal)) return "";
  return fmt::format(
      "; about {:.0f} samples per set would decide it (estimate from the runs' scatter{}; "
      "cheapest split {:.0f} of {} and {:.0f} of {})",
      n.equal, pooled ? " pooled over neighbouring rates" : "", n.a, name_a, n.b, name_b);
}

void strip_samples_words(std::string& reason) {
  for (std::size_t at = reason.find("; about "); at != std::string::npos;
       at = reason.find("; about ", at + 1)) {
    const std::size_t words = reason.find(" samples per set would decide it (", at);
    const std::size_t digits = reason.find_first_not_of("0123456789", at + 8);
    if (words == std::string::npos || digits != words || digits == at + 8) continue;
    const std::size_t close = reason.find(')', words);
    if (close == std::string::npos) return;
    reason.erase(at, close + 1 - at);
    return;
  }
}

void pool_window_scatter(std::vector<Verdict>& verdicts, const std::vector<ScatterSeries>& series,
                         Levels levels, double margin) {
  // series -> (rate, (s, dof)) for each set.
  std::map<int, std::vector<std::pair<double, std::pair<double, double>>>> set_a, set_b;
  for (const ScatterSeries& s : series) {
    const Verdict& v = verdicts.at(s.verdict);
    set_a[s.series].push_back(
        {s.log10_rate, {value_of(v, "scatter_a"), value_of(v, "samples_a") - 1}});
    set_b[s.series].push_back(
        {s.log10_rate, {value_of(v, "scatter_b"), value_of(v, "samples_b") - 1}});
  }
  for (const ScatterSeries& s : series) {
    Verdict& v = verdicts.at(s.verdict);
    if (!std::isfinite(value_of(v, "scatter_a"))) continue;
    const double sa = pooled_scatter(set_a[s.series], s.log10_rate),
                 sb = pooled_scatter(set_b[s.series], s.log10_rate);
    v.values["scatter_a_pooled"] = sa;
    v.values["scatter_b_pooled"] = sb;
    if (v.status != "inconclusive") continue;
    strip_samples_words(v.reason);
    const SamplesNeeded n =
        samples_needed(value_of(v, "difference"), sa, sb, s.cost_a, s.cost_b,
                       value_of(v, "samples_a"), value_of(v, "samples_b"), levels, margin);
    v.samples_needed = n.equal;
    v.values["samples_needed_a"] = n.a;
    v.values["samples_needed_b"] = n.b;
    // Before the reason's tail (e.g. phi_init's " | n256 ..."), after the verdict's own words.
    const std::size_t tail = v.reason.find(" | ");
    v.reason.insert(tail == std::string::npos ? v.reason.size() : tail,
                    samples_words(n, s.name_a, s.name_b, true));
  }
}

}  // namespace jam::checks
