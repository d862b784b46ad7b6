#include "stats/fit_scan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>


namespace jam::stats {
namespace {

// Two fits agree when their free parameters differ by at most this many combined sigma.
constexpr double kAgreement = 2.0;

bool agree(const ScalingFitResult& a, const ScalingFitResult& b) {
  auto close = [](double x, double ex, double y, double ey) {
    return std::abs(x - y) <= kAgreement * std::sqrt(ex * ex + ey * ey);
  };
  return close(a.phi_j, a.phi_j_err, b.phi_j, b.phi_j_err) &&
         close(a.rate_exponent, a.rate_exponent_err, b.rate_exponent, b.rate_exponent_err) &&
         close(a.inv_znu, a.inv_znu_err, b.inv_znu, b.inv_znu_err);
}

/// Whether the representative (rows[i]) stands on a plateau: every other fit of quality ok of
/// the same window agrees with it within kAgreement combined sigma. Without one, the words name
/// the largest move of beta, which the systematic error (scan_fits) covers.
std::string plateau_words(FitScan& scan, const std::vector<std::size_t>& rows, std::size_t i) {
  const ScalingFitResult& rep = *scan.rows[rows[i]].result;
  std::size_t compared = 0, far = rows.size();
  double worst = 0.0;
  bool flat = true;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const auto& other = scan.rows[rows[j]];
    if (j == i || !other.result || other.result->quality != "ok") continue;
    ++compared;
    flat = flat && agree(rep, *other.result);
    if (std::abs(other.result->beta - rep.beta) >= worst)
      worst = std::abs(other.result->beta - rep.beta), far = j;
  }
  scan.plateau = compared > 0 && flat;
  if (compared == 0) return "no other rate_max's fit of quality ok to compare: plateau unknown";
  if (flat)
    return fmt::format(
        "a plateau: phi_J, q and 1/(z nu) agree within {:g} sigma with the {} other fits of "
        "quality ok",
        kAgreement, compared);
  return fmt::format(
      "no plateau: the {} other fits of quality ok do not all agree within {:g} sigma (beta "
      "{:.3g} at rate_max {:.3g} against {:.3g}); the systematic error covers the drift",
      compared, kAgreement, scan.rows[rows[far]].result->beta, scan.rows[rows[far]].rate_max,
      rep.beta);
}

bool cleared(const RateClearance& c, double rate) {
  if (!c.cleared) return true;
  return std::any_of(c.cleared->begin(), c.cleared->end(),
                     [rate](double lr) { return std::abs(std::pow(10.0, lr) / rate - 1) < 1e-6; });
}

}  // namespace

RateClearance read_clearance(const FitVerdicts& verdicts, std::int64_t n, double fit_phi_init,
                             double lowest_phi_init) {
  RateClearance c;
  if (std::abs(fit_phi_init - lowest_phi_init) < 1e-9) {
    c.note = fmt::format(
        "phi_init {:g} is the campaign's lowest start: the phi_init check compares the others "
        "with it, so no verdict bears on its memory of the start; all its rates are used",
        fit_phi_init);
    return c;
  }
  // The first file (checks.json, then checks-phi_init.json) with a verdict on this ensemble.
  std::string file;
  std::vector<double> rates;
  for (const auto& v : verdicts.phi_init) {
    if (v.n != n || std::abs(v.phi_init - fit_phi_init) > 1e-9) continue;
    if (file.empty()) file = v.file;
    if (v.file != file) continue;
    if (v.pass) rates.push_back(v.log10_rate);
  }
  if (!file.empty()) {
    c.cleared = rates;
    c.note = fmt::format(
        "rates cleared by the phi_init check ({}): {}", file,
        rates.empty() ? std::string("none") : fmt::format("1e{:g}", fmt::join(rates, ", 1e")));
    return c;
  }
  c.note =
      "no phi_init verdict for the fitted ensembles (run `jam check phi_init`): all rates used";
  return c;
}

namespace {

FitScan scan_and_choose(std::vector<FitEnsemble> data, const StatsOptions& o,
                        const RateClearance& clearance, const std::string& variable) {
  FitScan scan;
  if (data.empty()) {
    scan.failure = fmt::format("no ensembles to fit at constant {}", variable);
    return scan;
  }
  std::sort(data.begin(), data.end(),
            [](const FitEnsemble& a, const FitEnsemble& b) { return a.rate > b.rate; });
  // rate_max from the fastest rate down to the third slowest, so every fit sees >= 3 rates
  // (or all of them when there are fewer).
  std::vector<double> rate_max;
  for (std::size_t k = 0; k < data.size(); ++k) {
    if (data.size() - k >= 3 || k == 0) rate_max.push_back(data[k].rate);
  }
  for (double half : o.half_windows) {
    for (double rm : rate_max) {
      ScanRow row;
      row.rate_max = rm;
      row.half_window = half;
      try {
        row.result = fit_scaling(data, fit_options(o, o.order, half, rm));
      } catch (const FitError& e) {
        row.failure = e.what();
      }
      scan.rows.push_back(std::move(row));
    }
  }
  // The narrowest window's rows, fastest rate_max first, that use cleared rates only.
  const double narrowest = *std::min_element(o.half_windows.begin(), o.half_windows.end());
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < scan.rows.size(); ++k) {
    if (scan.rows[k].half_window != narrowest) continue;
    bool all_cleared = true;
    for (const auto& e : data)
      if (e.rate <= scan.rows[k].rate_max * (1 + 1e-9))
        all_cleared = all_cleared && cleared(clearance, e.rate);
    if (all_cleared) rows.push_back(k);
  }
  for (std::size_t k = 0; k < scan.rows.size(); ++k)
    if (scan.rows[k].half_window == narrowest &&
        std::abs(std::log10(scan.rows[k].rate_max) - kPapersLog10RateMax) < 1e-6)
      scan.papers_protocol = k;
  if (rows.empty()) {
    scan.failure = "no rate_max whose rates the phi_init check all clears; " + clearance.note;
    return scan;
  }
  // The representative: the slowest rate_max whose fit is of quality ok (its own test: enough
  // points of every rate in the window, chi^2/dof, conditioning). The scaling form holds only
  // as rate -> 0, so the slowest adequate fit is the one least touched by corrections to
  // scaling; a rule that takes the fastest fit the slower ones agree with is pulled to the fast
  // rates, because slower fits carry 2-4x larger errors and agree with anything.
  for (std::size_t i = rows.size(); i-- > 0;) {
    const auto& candidate = scan.rows[rows[i]];
    if (!candidate.result || candidate.result->quality != "ok") continue;
    scan.chosen = rows[i];
    scan.chosen_fit = candidate.result;
    std::string slower;
    for (std::size_t j = i + 1; j < rows.size(); ++j)
      slower += fmt::format("{}rate_max {:.3g}: {}", slower.empty() ? "" : "; ",
                            scan.rows[rows[j]].rate_max,
                            scan.rows[rows[j]].result ? "quality poor ("
                                + scan.rows[rows[j]].result->quality_reason + ")"
                                                      : scan.rows[rows[j]].failure);
    scan.reason = fmt::format(
        "narrowest window (+-{:g}); rate_max {:.3g}: the slowest whose fit is of quality ok{}; "
        "{}; {}",
        narrowest, candidate.rate_max, slower.empty() ? "" : " (slower: " + slower + ")",
        plateau_words(scan, rows, i), clearance.note);
    return scan;
  }
  // No fit of quality ok: the slowest rate_max with a result, said so, and flagged poor.
  for (std::size_t i = rows.size(); i-- > 0;) {
    if (!scan.rows[rows[i]].result) continue;
    scan.chosen = rows[i];
    scan.chosen_fit = scan.rows[rows[i]].result;
    scan.reason = fmt::format(
        "narrowest window (+-{:g}); no fit of quality ok at any rate_max: the slowest with a "
        "result, {:.3g}, taken and flagged poor; {}",
        narrowest, scan.rows[rows[i]].rate_max, clearance.note);
    ScalingFitResult& r = *scan.chosen_fit;
    r.quality = "poor";
    r.quality_reason += std::string(r.quality_reason.empty() ? "" : "; ") +
                        "no fit of the scan's narrowest window is of quality ok";
    return scan;
  }
  scan.failure = scan.rows[rows.back()].failure;
  return scan;
}

}  // namespace

FitScan scan_fits(std::vector<FitEnsemble> data, const StatsOptions& o,
                  const RateClearance& clearance, const std::string& variable) {
  FitScan scan = scan_and_choose(std::move(data), o, clearance, variable);
  const ScalingFitResult* rep = scan.representative();
  if (!rep) return scan;
  // The systematic error of the scan's choices (window, rate_max): the largest distance of any
  // fit of quality ok from the representative. It is measured on planted corrections to
  // scaling (tests/test_fit_scan.cpp): +-2 sqrt(jackknife^2 + systematic^2) covers the truth.
  const double v0[3] = {rep->phi_j, rep->beta, rep->y};
  double far[3] = {0, 0, 0};
  for (const ScanRow& row : scan.rows) {
    if (!row.result || row.result->quality != "ok") continue;
    const double v[3] = {row.result->phi_j, row.result->beta, row.result->y};
    for (int k = 0; k < 3; ++k) far[k] = std::max(far[k], std::abs(v[k] - v0[k]));
    ++scan.systematic.fits;
  }
  if (scan.systematic.fits >= 2) {
    scan.systematic.phi_j = far[0];
    scan.systematic.beta = far[1];
    scan.systematic.y = far[2];
  }
  return scan;
}

}  // namespace jam::stats
