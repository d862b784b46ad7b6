#include "stats/averages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "campaign/grid_limit.hpp"

namespace jam::stats {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

void finalize(GridAverage& a) {
  a.means.clear();
  for (const auto& table : a.tables) {
    std::vector<SampleMean> column(a.grid.size());
    for (std::size_t k = 0; k < a.grid.size(); ++k) {
      SampleAccumulator acc;
      for (const auto& row : table) acc.add(row[k]);
      column[k] = acc.finalize();
    }
    a.means.push_back(std::move(column));
  }
}

namespace {

std::vector<double> grid_between(double lo, double hi, double step) {
  std::vector<double> g;
  const double a = std::ceil(lo / step - 1e-9), b = std::floor(hi / step + 1e-9);
  // Grid indices must be whole numbers a long long holds exactly: a value of 1e300 (or
  // 5.4e154, a single flipped exponent bit of 4.0) in a run would otherwise overflow the
  // conversion below and ask for a grid of any size (the count bound passed it).
  if (!(std::abs(a) < 0x1p53 && std::abs(b) < 0x1p53)) {
    throw std::runtime_error(fmt::format(
        "a grid of step {:g} from {:g} to {:g}: values beyond any packing or contact number", step,
        lo, hi));
  }
  const double count = b - a + 1;
  // A bound before anything is allocated (campaign/grid_limit.hpp).
  if (!(count <= kMaxGridPoints)) {
    throw std::runtime_error(
        fmt::format("a grid of step {:g} from {:g} to {:g} has {:.3g} points (at most {:g})", step,
                    lo, hi, count, kMaxGridPoints));
  }
  if (count < 1) return g;
  const auto first = static_cast<long long>(a), last = static_cast<long long>(b);
  // Grid values are exactly k * step, whatever the samples: the same run then gives the same
  // numbers in any set of samples (a regression baseline compares them bitwise). k * step can
  // land an ulp outside [lo, hi] (0.86 = 430 * 0.002 + 1e-16); interpolate() takes such a
  // point as the end point.
  for (long long k = first; k <= last; ++k) g.push_back(static_cast<double>(k) * step);
  return g;
}

}  // namespace

const std::vector<std::vector<double>>& GridAverage::table(const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return tables[k];
  throw std::out_of_range("no observable " + name);
}

const std::vector<SampleMean>& GridAverage::mean(const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return means[k];
  throw std::out_of_range("no observable " + name);
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double x0) {
  if (x.empty()) return kNaN;
  // Within round-off of an end point counts as the end point (grid values k * step).
  const double slack = 1e-12 * std::max(std::abs(x.front()), std::abs(x.back()));
  if (x0 < x.front() && x0 >= x.front() - slack) return y.front();
  if (x0 > x.back() && x0 <= x.back() + slack) return y.back();
  if (x0 < x.front() || x0 > x.back()) return kNaN;
  const auto it = std::upper_bound(x.begin(), x.end(), x0);
  if (it == x.end()) return y.back();
  const std::size_t i = static_cast<std::size_t>(it - x.begin());
  if (i == 0) return y.front();
  const double t = (x0 - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

GridAverage average_at_constant_phi(const std::vector<RunCurves>& samples, double phi_step,
                                    Span span) {
  if (samples.empty()) throw std::invalid_argument("average: no samples");
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  if (span == Span::any_sample) hi = lo;
  for (const auto& r : samples) {
    lo = std::max(lo, r.phi.front());
    hi = span == Span::any_sample ? std::max(hi, r.phi.back()) : std::min(hi, r.phi.back());
  }
  GridAverage a;
  a.grid_name = "packing_fraction";
  a.grid = grid_between(lo, hi, phi_step);
  // Runs of other simulators may carry no Z (docs/cross-simulator.md): then pressure alone.
  const bool with_z = std::all_of(samples.begin(), samples.end(),
                                  [](const RunCurves& r) { return !r.contacts.empty(); });
  a.names = {"pressure"};
  if (with_z) a.names.push_back("contacts_per_particle");
  const bool with_nr = std::all_of(samples.begin(), samples.end(), [](const RunCurves& r) {
    return !r.contacts_no_rattlers.empty();
  });
  if (with_nr) a.names.push_back("contacts_per_particle_no_rattlers");
  a.tables.assign(a.names.size(), {});
  for (const auto& r : samples) {
    a.sample_ids.push_back(r.sample);
    std::vector<const std::vector<double>*> ys = {&r.pressure};
    if (with_z) ys.push_back(&r.contacts);
    if (with_nr) ys.push_back(&r.contacts_no_rattlers);
    for (std::size_t o = 0; o < ys.size(); ++o) {
      std::vector<double> row(a.grid.size());
      for (std::size_t k = 0; k < a.grid.size(); ++k)
        row[k] = interpolate(r.phi, *ys[o], a.grid[k]);
      a.tables[o].push_back(std::move(row));
    }
  }
  finalize(a);
  return a;
}

GridAverage average_at_constant_z(const std::vector<RunCurves>& samples, double z_step,
                                  bool no_rattlers, Span span) {
  if (samples.empty()) throw std::invalid_argument("average: no samples");
  auto z_of = [&](const RunCurves& r) -> const std::vector<double>& {
    if (no_rattlers && r.contacts_no_rattlers.empty()) {
      throw std::invalid_argument(
          "average at constant Z without rattlers: the runs did not store it (run with rattlers "
          "= true)");
    }
    if (r.contacts.empty())
      throw std::invalid_argument("average at constant Z: a run stored no contacts_per_particle");
    return no_rattlers ? r.contacts_no_rattlers : r.contacts;
  };
  // Common range: above every run's start, below every run's largest Z (any_sample: below the
  // largest Z of any run; a run that never reaches a grid value has NaN there).
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  if (span == Span::any_sample) hi = lo;
  for (const auto& r : samples) {
    const auto& z = z_of(r);
    lo = std::max(lo, z.front());
    const double top = *std::max_element(z.begin(), z.end());
    hi = span == Span::any_sample ? std::max(hi, top) : std::min(hi, top);
  }
  GridAverage a;
  a.grid_name = no_rattlers ? "contacts_per_particle_no_rattlers" : "contacts_per_particle";
  for (double g : grid_between(lo, hi, z_step))
    if (g > lo && g <= hi) a.grid.push_back(g);
  a.names = {"packing_fraction", "pressure"};
  a.tables.assign(2, {});
  for (const auto& r : samples) {
    a.sample_ids.push_back(r.sample);
    const auto& z = z_of(r);
    std::vector<double> phi_row(a.grid.size(), kNaN), p_row(a.grid.size(), kNaN);
    std::size_t i = 0;  // Z grid increasing: the first crossing of Z_k is at or after Z_{k-1}'s
    for (std::size_t k = 0; k < a.grid.size(); ++k) {
      while (i + 1 < z.size() && !(z[i] < a.grid[k] && z[i + 1] >= a.grid[k])) ++i;
      if (i + 1 >= z.size()) break;
      const double t = (a.grid[k] - z[i]) / (z[i + 1] - z[i]);
      phi_row[k] = r.phi[i] + t * (r.phi[i + 1] - r.phi[i]);
      p_row[k] = r.pressure[i] + t * (r.pressure[i + 1] - r.pressure[i]);
    }
    a.tables[0].push_back(std::move(phi_row));
    a.tables[1].push_back(std::move(p_row));
  }
  finalize(a);
  return a;
}

}  // namespace jam::stats
