#include "stats/papers_protocol.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>


namespace jam::stats {
namespace {

constexpr double kPhiTolerance = 1e-9;

bool rate_fitted(double log10_rate) { return log10_rate <= kPapersLog10RateMax + 1e-9; }

/// Whether the finite_size check's pooled constant-phi verdicts for (fitted sizes, phi_init)
/// pass at every fitted rate, as declared to the fit (fit_verdicts.hpp: DIR/checks.json's);
/// the words say what was read.
std::pair<bool, std::string> sizes_may_be_pooled(const FitVerdicts& verdicts, double phi_init,
                                                 const std::set<double>& rates) {
  if (!verdicts.checks_json)
    return {false, "no finite_size verdicts (checks.json) to allow pooling"};
  std::map<double, bool> passed;  // rate -> every pooled constant-phi verdict passed
  for (const auto& v : verdicts.finite_size) {
    if (std::abs(v.phi_init - phi_init) > kPhiTolerance) continue;
    const auto it = passed.find(v.log10_rate);
    passed[v.log10_rate] = it == passed.end() ? v.pass : it->second && v.pass;
  }
  for (double rate : rates) {
    const auto it = passed.find(rate);
    if (it == passed.end())
      return {false, fmt::format("no finite_size verdict at rate 1e{:g} to allow pooling", rate)};
    if (!it->second)
      return {false,
              fmt::format("the finite_size check does not pass at rate 1e{:g}: not pooled", rate)};
  }
  return {true, "pooled: the finite_size check's pooled verdicts at constant phi pass at every "
                "fitted rate"};
}

/// The ensembles of one rate as one: the samples of every size on the packings they share,
/// each size's sample ids kept apart (a sample shares its start across rates, not sizes).
FitEnsemble pooled(const std::vector<const EnsembleStats*>& sizes) {
  FitEnsemble f;
  f.rate = std::pow(10.0, sizes.front()->key.log10_rate);
  const auto& first = sizes.front()->constant_phi.grid;
  for (double phi : first) {
    const bool shared = std::all_of(sizes.begin(), sizes.end(), [&](const EnsembleStats* e) {
      const auto& g = e->constant_phi.grid;
      return std::any_of(g.begin(), g.end(),
                         [&](double x) { return std::abs(x - phi) < kPhiTolerance; });
    });
    if (shared) f.phi.push_back(phi);
  }
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const GridAverage& a = sizes[k]->constant_phi;
    const auto& table = a.table("pressure");
    std::vector<std::size_t> at;
    for (double phi : f.phi)
      at.push_back(static_cast<std::size_t>(
          std::find_if(a.grid.begin(), a.grid.end(),
                       [&](double x) { return std::abs(x - phi) < kPhiTolerance; }) -
          a.grid.begin()));
    for (std::size_t s = 0; s < table.size(); ++s) {
      std::vector<double> row;
      for (std::size_t i : at) row.push_back(table[s][i]);
      f.pressure.push_back(std::move(row));
      // Ids of the k-th size start past 2^40, beyond any sample index a campaign allows.
      f.sample_ids.push_back(a.sample_ids[s] + static_cast<std::int64_t>(k) * (std::int64_t{1} << 40));
    }
  }
  return f;
}

}  // namespace

std::optional<PapersProtocolFit> fit_papers_protocol(const CampaignStats& s,
                                                     const StatsOptions& o) {
  std::map<double, std::vector<const EnsembleStats*>> by_rate;
  std::set<std::int64_t> sizes;
  for (const auto& e : s.ensembles) {
    if (std::abs(e.key.phi_init - s.fit_phi_init) > kPhiTolerance || e.key.n == 0) continue;
    if (!rate_fitted(e.key.log10_rate)) continue;
    by_rate[e.key.log10_rate].push_back(&e);
    sizes.insert(e.key.n);
  }
  if (by_rate.empty()) return std::nullopt;
  std::set<double> rates;
  for (const auto& [rate, _] : by_rate) rates.insert(rate);
  auto [pool, why] = sizes.size() >= 2 ? sizes_may_be_pooled(o.verdicts, s.fit_phi_init, rates)
                                       : std::pair{false, std::string("a single size")};
  std::vector<FitEnsemble> data;
  for (auto& [rate, ensembles] : by_rate) {
    if (!pool) {
      std::erase_if(ensembles, [&](const EnsembleStats* e) { return e->key.n != *sizes.rbegin(); });
      if (ensembles.empty()) continue;
    }
    data.push_back(pooled(ensembles));
  }
  PapersProtocolFit p;
  p.row.rate_max = std::pow(10.0, kPapersLog10RateMax);
  p.row.half_window = *std::min_element(o.half_windows.begin(), o.half_windows.end());
  p.how = fmt::format(
      "the paper's protocol: {}; order {}, |x| <= 1, rate_max 10^{:g}, window +-{:g}; N {}",
      pool ? why : "the largest size alone (" + why + ")", kPapersOrder, kPapersLog10RateMax,
      p.row.half_window,
      pool ? fmt::format("{}", fmt::join(sizes, " and ")) : std::to_string(*sizes.rbegin()));
  try {
    p.result = fit_scaling(data, fit_options(o, kPapersOrder, p.row.half_window,
                                             p.row.rate_max * (1 + 1e-9)));
  } catch (const FitError& e) {
    p.failure = e.what();
  }
  return p;
}

}  // namespace jam::stats
