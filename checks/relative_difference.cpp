#include "checks/relative_difference.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace jam::checks {
namespace {

struct Moments {
  std::vector<double> mean, var_of_mean;
};

Moments moments(const std::vector<const std::vector<double>*>& rows,
                const std::vector<std::size_t>& points) {
  Moments m;
  const double s = static_cast<double>(rows.size());
  for (std::size_t k : points) {
    double mean = 0.0;
    for (const auto* r : rows) mean += (*r)[k] / s;
    double ss = 0.0;
    for (const auto* r : rows) ss += ((*r)[k] - mean) * ((*r)[k] - mean);
    m.mean.push_back(mean);
    m.var_of_mean.push_back(ss / (s - 1.0) / s);
  }
  return m;
}

// Delta and sigma (first-order propagation of both standard errors) and T.
double statistic(const std::vector<const std::vector<double>*>& a,
                 const std::vector<const std::vector<double>*>& b,
                 const std::vector<std::size_t>& points, std::vector<double>* delta,
                 std::vector<double>* sigma) {
  const Moments ma = moments(a, points), mb = moments(b, points);
  double t = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double sum = ma.mean[k] + mb.mean[k];
    const double d = 2.0 * (ma.mean[k] - mb.mean[k]) / sum;
    // d Delta / d p_A = 4 p_B / sum^2, d Delta / d p_B = -4 p_A / sum^2.
    const double s = 4.0 / (sum * sum) *
                     std::sqrt(mb.mean[k] * mb.mean[k] * ma.var_of_mean[k] +
                               ma.mean[k] * ma.mean[k] * mb.var_of_mean[k]);
    if (delta) delta->push_back(d);
    if (sigma) sigma->push_back(s);
    if (s > 0) t = std::max(t, std::abs(d) / s);
  }
  return t;
}

}  // namespace

RelativeDifference compare_run_sets(const std::vector<std::vector<double>>& a,
                                    const std::vector<std::vector<double>>& b, double alpha,
                                    int permutations, std::uint64_t seed) {
  if (a.size() < 2 || b.size() < 2) {
    throw std::invalid_argument("compare: each run set needs at least 2 samples");
  }
  const std::size_t m = a.front().size();
  std::vector<std::size_t> points;
  for (std::size_t k = 0; k < m; ++k) {
    bool ok = true;
    for (const auto& r : a) ok = ok && std::isfinite(r[k]) && r[k] > 0;
    for (const auto& r : b) ok = ok && std::isfinite(r[k]) && r[k] > 0;
    if (ok) points.push_back(k);
  }
  if (points.empty()) throw std::invalid_argument("compare: no common grid points");
  std::vector<const std::vector<double>*> ra, rb, all;
  for (const auto& r : a) ra.push_back(&r);
  for (const auto& r : b) rb.push_back(&r);
  all = ra;
  all.insert(all.end(), rb.begin(), rb.end());

  RelativeDifference r;
  r.points = points;
  r.statistic = statistic(ra, rb, points, &r.delta, &r.sigma);
  // Permutations of whole runs between the two sets.
  std::mt19937_64 rng(seed);
  std::vector<std::size_t> order(all.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> null;
  null.reserve(static_cast<std::size_t>(permutations));
  int at_least = 0;
  for (int p = 0; p < permutations; ++p) {
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<const std::vector<double>*> pa, pb;
    for (std::size_t i = 0; i < all.size(); ++i) (i < a.size() ? pa : pb).push_back(all[order[i]]);
    const double t = statistic(pa, pb, points, nullptr, nullptr);
    null.push_back(t);
    at_least += t >= r.statistic;
  }
  r.permutations = permutations;
  r.p_value = (1.0 + at_least) / (1.0 + permutations);
  std::sort(null.begin(), null.end());
  r.critical = null[std::min(null.size() - 1,
                             static_cast<std::size_t>(std::ceil((1.0 - alpha) * null.size())) - 1)];
  std::vector<double> sigmas = r.sigma;
  for (std::size_t k = 0; k < r.delta.size(); ++k) {
    r.excluded_above = std::max(r.excluded_above, std::abs(r.delta[k]) + r.critical * r.sigma[k]);
  }
  std::nth_element(sigmas.begin(), sigmas.begin() + static_cast<long>(sigmas.size() / 2),
                   sigmas.end());
  r.detectable = r.critical * sigmas[sigmas.size() / 2];
  return r;
}

MeanDifference compare_means(std::vector<double> a, std::vector<double> b, double alpha,
                             int permutations, std::uint64_t seed) {
  auto finite = [](std::vector<double>& v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }),
            v.end());
  };
  finite(a);
  finite(b);
  if (a.size() < 2 || b.size() < 2)
    throw std::invalid_argument("compare: each set needs at least 2 values");
  auto stat = [](const std::vector<double>& all, std::size_t na, double* diff, double* sigma) {
    double ma = 0, mb = 0, va = 0, vb = 0;
    const std::size_t nb = all.size() - na;
    for (std::size_t i = 0; i < na; ++i) ma += all[i] / static_cast<double>(na);
    for (std::size_t i = na; i < all.size(); ++i) mb += all[i] / static_cast<double>(nb);
    for (std::size_t i = 0; i < na; ++i)
      va += (all[i] - ma) * (all[i] - ma) / static_cast<double>(na - 1);
    for (std::size_t i = na; i < all.size(); ++i)
      vb += (all[i] - mb) * (all[i] - mb) / static_cast<double>(nb - 1);
    const double s = std::sqrt(va / static_cast<double>(na) + vb / static_cast<double>(nb));
    if (diff) *diff = ma - mb;
    if (sigma) *sigma = s;
    return s > 0 ? std::abs(ma - mb) / s : 0.0;
  };
  std::vector<double> all = a;
  all.insert(all.end(), b.begin(), b.end());
  MeanDifference r;
  r.statistic = stat(all, a.size(), &r.difference, &r.sigma);
  std::mt19937_64 rng(seed);
  std::vector<double> null;
  int at_least = 0;
  for (int p = 0; p < permutations; ++p) {
    std::shuffle(all.begin(), all.end(), rng);
    const double t = stat(all, a.size(), nullptr, nullptr);
    null.push_back(t);
    at_least += t >= r.statistic;
  }
  r.p_value = (1.0 + at_least) / (1.0 + permutations);
  std::sort(null.begin(), null.end());
  r.critical = null[std::min(null.size() - 1,
                             static_cast<std::size_t>(std::ceil((1.0 - alpha) * null.size())) - 1)];
  r.excluded_above = std::abs(r.difference) + r.critical * r.sigma;
  r.detectable = r.critical * r.sigma;
  return r;
}

}  // namespace jam::checks
