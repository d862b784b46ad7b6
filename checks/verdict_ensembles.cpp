#include "checks/verdict_ensembles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "checks/check_registry.hpp"

namespace jam::checks::samples {
namespace {

std::optional<double> get(const Values& v, const char* key) {
  const auto it = v.find(key);
  return it == v.end() ? std::nullopt : std::optional<double>(it->second);
}

EnsembleId id(double n, double phi_init, double log10_rate) {
  return EnsembleId{static_cast<std::int64_t>(std::llround(n)), phi_init, log10_rate};
}

std::vector<EnsembleId> sizes(const Values& v) {
  const auto na = get(v, "n_a"), nb = get(v, "n_b"), phi = get(v, "phi_init"),
             rate = get(v, "log10_rate");
  if (!(na && nb && phi && rate)) return {};
  return {id(*na, *phi, *rate), id(*nb, *phi, *rate)};
}

std::vector<EnsembleId> starts(const Values& v) {
  const auto n = get(v, "n"), phi = get(v, "phi_init"), low = get(v, "lowest_phi_init"),
             rate = get(v, "log10_rate");
  if (!(n && phi && low && rate)) return {};
  return {id(*n, *phi, *rate), id(*n, *low, *rate)};
}

std::vector<EnsembleId> rates(const Values& v) {
  const auto n = get(v, "n"), phi = get(v, "phi_init"), slow = get(v, "log10_rate_slow"),
             fast = get(v, "log10_rate_faster");
  if (!(n && phi && slow && fast)) return {};
  return {id(*n, *phi, *slow), id(*n, *phi, *fast)};
}

std::vector<EnsembleId> one(const Values& v) {
  const auto n = get(v, "n"), phi = get(v, "phi_init"), rate = get(v, "log10_rate");
  if (!(n && phi && rate)) return {};
  return {id(*n, *phi, *rate)};
}

std::vector<EnsembleId> none(const Values&) {
  return {};
}

std::vector<Values> planned_none(const Campaign&) {
  return {};
}

/// The smallest size against the largest, at every phi_init and rate, constant phi and Z.
std::vector<Values> planned_sizes(const Campaign& c) {
  std::vector<Values> out;
  if (c.sizes.size() < 2) return out;
  const auto [lo, hi] = std::minmax_element(c.sizes.begin(), c.sizes.end());
  for (double phi : c.phi_init)
    for (double r : c.log10_rates)
      for (double z : {0.0, 1.0})
        out.push_back({{"n_a", static_cast<double>(*lo)},
                       {"n_b", static_cast<double>(*hi)},
                       {"phi_init", phi},
                       {"log10_rate", r},
                       {"constant_z", z}});
  return out;
}

/// Every phi_init above the lowest against the lowest, at every size and rate.
std::vector<Values> planned_starts(const Campaign& c) {
  std::vector<Values> out;
  if (c.phi_init.size() < 2) return out;
  const double low = *std::min_element(c.phi_init.begin(), c.phi_init.end());
  for (auto n : c.sizes)
    for (double r : c.log10_rates)
      for (double phi : c.phi_init)
        if (phi != low)
          out.push_back({{"n", static_cast<double>(n)},
                         {"phi_init", phi},
                         {"lowest_phi_init", low},
                         {"log10_rate", r}});
  return out;
}

constexpr std::string_view kSizeKeys[] = {"n",        "n_a",        "n_b",
                                          "phi_init", "log10_rate", "constant_z"};
constexpr std::string_view kStartKeys[] = {"n", "phi_init", "lowest_phi_init", "log10_rate"};
constexpr std::string_view kRateKeys[] = {"n", "phi_init", "log10_rate_slow", "log10_rate_faster"};
// Both families' starts too: a campaign with several phi_init compares n_a against n_b at
// each of them, and each size's starts against the lowest.
constexpr std::string_view kFitKeys[] = {"n_a", "n_b", "phi_init_a", "phi_init_b"};
constexpr std::string_view kEnsembleKeys[] = {"n", "phi_init", "log10_rate"};
constexpr std::string_view kAnyKeys[] = {"n", "n_a", "n_b", "phi_init", "log10_rate", "constant_z"};

}  // namespace

const Samples kSizesPlanned{&sizes, kSizeKeys, &planned_sizes};
const Samples kSizes{&sizes, kSizeKeys, &planned_none};
const Samples kStartsPlanned{&starts, kStartKeys, &planned_starts};
const Samples kStarts{&starts, kStartKeys, &planned_none};
const Samples kRates{&rates, kRateKeys, &planned_none};
const Samples kEnsemble{&one, kEnsembleKeys, &planned_none};
const Samples kFits{&none, kFitKeys, &planned_none};
const Samples kNotBySamples{&none, kAnyKeys, &planned_none};

}  // namespace jam::checks::samples

namespace jam::checks {

const Samples& samples_of(const Verdict& v) {
  const CheckEntry* e = find_check(v.check);
  if (!e) throw std::logic_error("a verdict of an unregistered check: " + v.check);
  return *e->samples;
}

std::string verdict_identity(const Verdict& v) {
  std::string key = v.check;
  if (!v.region.empty() && v.region != "pooled") key += " region=" + v.region;
  for (const std::string_view k : samples_of(v).identity)
    if (const auto it = v.values.find(std::string(k)); it != v.values.end())
      key += fmt::format(" {}={:.9g}", k, it->second);
  return key;
}

}  // namespace jam::checks
