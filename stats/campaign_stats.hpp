#pragma once
// `jam stats DIR`: everything the statistics stage computes from a campaign directory, and
// the options that steer it. Reads run files only; writes DIR/stats.h5 (reference/schema.md).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stats/averages.hpp"
#include "stats/fit_verdicts.hpp"
#include "stats/run_coverage.hpp"
#include "stats/run_curves.hpp"
#include "stats/scaling_fit.hpp"

namespace jam::stats {

struct StatsOptions {
  double z_step = 0.01;                // grid spacing in Z for constant-Z averages
  bool no_rattlers = false;            // constant-Z averages with rattlers removed
  bool pool_sizes = false;             // average the sizes together (after the finite-size check)
  std::optional<double> fit_phi_init;  // ensembles of this phi_init are fitted (default: lowest)
  int order = 5;
  std::optional<double> fixed_phi_j, fixed_rate_exponent, fixed_inv_znu;
  std::vector<double> half_windows = {0.03, 0.02, 0.01};  // phi windows: fitted phi_J +- these
  bool fit = true;
  // The verdicts the fit may use, declared by the caller (fit_verdicts.hpp); none by default.
  FitVerdicts verdicts;
};

/// The options of one scaling fit of the campaign: its order and held parameters, at this
/// window and rate_max (the scan's rows, the per-size fits and the paper's protocol alike).
inline ScalingFitOptions fit_options(const StatsOptions& o, int order, double half_window,
                                     double rate_max) {
  ScalingFitOptions f;
  f.order = order;
  f.fixed_phi_j = o.fixed_phi_j;
  f.fixed_rate_exponent = o.fixed_rate_exponent;
  f.fixed_inv_znu = o.fixed_inv_znu;
  f.half_window = half_window;
  f.rate_max = rate_max;
  return f;
}

/// phi_Ji over the samples of an ensemble (runs with jamming_point).
struct JammingStats {
  std::vector<double> samples;  // per run, NaN where the run did not bracket it
  std::vector<std::int64_t> sample_ids;
  SampleMean mean;      // over the runs that found it
  double spread = 0.0;  // standard deviation over samples, Delta phi_J
};

/// phi_Ji over an ensemble's samples (NaN: a run that did not bracket it): mean, error, spread.
JammingStats jamming_stats(std::vector<double> samples, std::vector<std::int64_t> sample_ids);

struct EnsembleStats {
  EnsembleKey key;
  GridAverage constant_phi;
  std::optional<GridAverage> constant_z;
  std::optional<JammingStats> jamming;
  // What each run covers (run_coverage.hpp); absent in a refit of a file written before it.
  std::optional<RunCoverage> coverage;
  // phi'_init of a chained rate (its runs start from the faster rate's configuration there);
  // 0: started from the relaxed random start.
  double chain_phi_init = 0.0;
};

struct ScanRow {
  double rate_max = 0, half_window = 0;
  std::optional<ScalingFitResult> result;
  std::string failure;  // why the fit could not be done
};

/// The paper's scan (its Fig. 2): the fit for every phi window and rate_max, and the row taken
/// as representative, with the reason.
struct FitScan {
  std::vector<ScanRow> rows;          // each fit with its own quality test
  std::optional<std::size_t> chosen;  // the representative row
  std::string reason;                 // why that row
  std::string failure;                // why there is none
  // The chosen row's fit as the representative: flagged poor when no plateau confirms it,
  // while its row in `rows` keeps the verdict of its own quality test.
  std::optional<ScalingFitResult> chosen_fit;
  const ScalingFitResult* representative() const { return chosen_fit ? &*chosen_fit : nullptr; }
  // The error of the choices the scan makes (window, rate_max), beside the representative's
  // jackknife error: the largest distance of phi_J, beta and y of any row of quality ok from
  // the representative's (NaN with fewer than two such rows). It covers those choices and the
  // drift they show, not the order of ln f or pooling.
  struct Spread {
    double phi_j = NAN, beta = NAN, y = NAN;
    std::size_t fits = 0;  // the rows of quality ok it spans
  } systematic;
  // Whether every other fit of quality ok of the representative's window agrees with it
  // within 2 sigma (the reason says which fit moves most when not).
  bool plateau = false;
  // The paper's protocol (its Fig. 3 and supplement): the narrowest window at rate_max
  // 10^-6.5, labelled, never chosen for it; absent when the campaign has no such rate_max.
  std::optional<std::size_t> papers_protocol;
};

/// The fewest rates a scaling fit can use (stats/scaling_fit.cpp: with 2, phi_J and q trade
/// off). A design with fewer among its fitted ensembles gets no fit attempted at all:
/// fit_campaign says so in FitScan::failure and leaves the scan empty.
constexpr std::size_t kFitRatesMin = 3;

/// The paper's representative rate_max (its Figs. 3-4: "rate_max = 10^-6.5").
constexpr double kPapersLog10RateMax = -6.5;

/// Rates of the fitted ensembles that the phi_init check clears (no memory of the start within
/// its margin), read from DIR/checks.json or checks-phi_init.json; empty optional when no
/// verdict applies (then every rate is used, and the reason says so).
struct RateClearance {
  std::optional<std::vector<double>> cleared;  // log10 rates
  std::string note;
};

/// The scaling fit of one (N, phi_init) at the representative fit's window, rate_max and
/// order, for comparing fitted parameters between sizes and starts (the fit_parameters check).
struct FamilyFit {
  std::int64_t n = 0;
  double phi_init = 0.0;
  std::optional<ScalingFitResult> result;
  std::string failure;  // why there is none
};

/// The paper's protocol fitted as one labelled row (stats/papers_protocol.hpp).
struct PapersProtocolFit {
  std::optional<ScalingFitResult> result;
  ScanRow row;          // its rate_max and window (the result is held in `result`)
  std::string how;      // which sizes and why, the order, the rate_max
  std::string failure;  // why there is no result
};

struct CampaignStats {
  CampaignData data;
  std::vector<EnsembleStats> ensembles;
  FitScan fit;    // at constant phi
  FitScan fit_z;  // the same fit on the averages at constant Z (phi = <phi> there)
  std::vector<FamilyFit> families;  // every (N, phi_init) fitted as the representative
  std::optional<PapersProtocolFit> papers_protocol;  // none without a rate <= 10^-6.5
  RateClearance clearance;
  // What the fit was of and the verdicts it consulted (fit_verdicts.hpp).
  FitSelection fit_selection;
  FitVerdicts fit_verdicts;
  double fit_phi_init = 0.0;
  std::int64_t fit_size = 0;  // 0: pooled
  std::int64_t runs_averaged = 0, runs_skipped = 0;
  std::string refit_from;  // when refitted from an earlier stats.h5: says so
  // The digest of the runs it was computed from (stats_inputs.hpp), taken before they were
  // read; a refit carries over the earlier file's. "": not known.
  std::string inputs_checksum;
  double wall_time = 0.0;  // seconds spent reading and averaging (provenance for reports)
};

CampaignStats compute_campaign_stats(const std::string& directory, const StatsOptions& options);

/// The fits (fit_scan.hpp) of s's ensembles, with the verdicts options.verdicts declares.
void fit_campaign(CampaignStats& s, const StatsOptions& options);

/// s.families: every (N, phi_init) fitted at the representative fit's window and rate_max
/// (none when there is no representative fit).
void fit_families(CampaignStats& s, const StatsOptions& options);

/// The averages stored in DIR/stats.h5 (its per-sample tables), refitted with `options`,
/// without reading a run: for stored results whose runs are not kept. Sizes are pooled only if
/// they were pooled there.
CampaignStats refit_campaign_stats(const std::string& directory, const StatsOptions& options);

/// Writes DIR/stats.h5 atomically.
void write_stats_file(const std::string& path, const CampaignStats& stats,
                      const StatsOptions& options);

/// The summary table for terminals and CI logs.
std::string format_stats_summary(const CampaignStats& stats);

}  // namespace jam::stats
