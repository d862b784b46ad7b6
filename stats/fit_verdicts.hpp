#pragma once
// The verdicts the scaling fit may use, as a declared input: data flow from stats to checks,
// so stats/ never reads a verdict file. The caller (design/stats_stage.cpp,
// declared_fit_verdicts, for `jam stats`, the pilot, the looks of --until-decided and `jam
// pipeline`) reads DIR/checks.json through checks/fit_inputs.hpp (checks::fit_verdicts, over
// verdict_file.hpp) and passes what it found here; stats.h5 records whether the fit used them
// and a digest of them (`fit_verdicts`, `fit_verdicts_checksum`), which `jam pipeline`
// compares to decide whether the fit is redone. Two uses:
//   - the phi_init check's verdicts clear the rates of a fitted phi_init above the lowest
//     (fit_scan.hpp, read_clearance);
//   - the finite_size check's pooled verdicts at constant phi allow the paper's protocol to
//     pool sizes (papers_protocol.hpp).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "stats/run_curves.hpp"

namespace jam::stats {

struct FitVerdicts {
  /// One verdict as the fit reads it.
  struct Judged {
    std::int64_t n = 0;  // phi_init verdicts: the size; finite_size: 0
    double phi_init = 0, log10_rate = 0;
    bool pass = false;
    std::string file;  // the verdict file it is from ("checks.json", "checks-phi_init.json")
  };
  std::vector<Judged> phi_init;     // the phi_init check's, in the order of their files
  std::vector<Judged> finite_size;  // finite_size's pooled verdicts at constant phi
  /// The files read ("checks.json, checks-phi_init.json"); "" when none was given.
  std::string files;
  bool checks_json = false;  // DIR/checks.json was read (finite_size's verdicts come from it)
  /// FNV-1a over the bytes of those files (provenance): "" when none.
  std::string files_checksum;

  bool empty() const { return phi_init.empty() && finite_size.empty(); }
  /// A digest of the verdicts above and whether checks.json was read (not of the files: their
  /// time stamps and the verdicts a fit does not read leave it unchanged), 16 hex digits;
  /// "none" when there are none and no checks.json.
  std::string checksum() const;
};

/// What a fit consults of the verdicts: the fitted size and phi_init, the campaign's lowest
/// phi_init, and the sizes and rates the paper's protocol fits (at most 10^-6.5).
struct FitSelection {
  bool fitted = false;  // false: no fit (--no-fit), nothing consulted
  std::int64_t n = 0;
  double phi_init = 0, lowest_phi_init = 0;
  std::set<std::int64_t> papers_sizes;
  std::set<double> papers_rates;
};

/// The selection of a fit of these ensembles at fit_phi_init and fit_size.
FitSelection fit_selection(const std::vector<EnsembleKey>& ensembles, double fit_phi_init,
                           std::int64_t fit_size);

/// The verdicts of `all` that a fit of `s` consults: the phi_init verdicts of its ensembles
/// when its phi_init is not the lowest (read_clearance), the finite_size verdicts at its
/// phi_init (and whether checks.json was read) when the paper's protocol may pool two or more
/// sizes (sizes_may_be_pooled). The fit's result depends on these alone, so stats.h5 records
/// them (`fit_verdicts`, `fit_verdicts_checksum`) and is the same whether or not `jam check`
/// ran when they are none.
FitVerdicts consulted(const FitVerdicts& all, const FitSelection& s);

/// "" when DIR/stats.h5's fit consulted what `now` holds of the verdicts it would consult
/// (or records none: written before it recorded them, or unreadable, which the other checks
/// of stats.h5 report); otherwise why not, in words.
std::string fit_verdicts_change(const std::string& directory, const FitVerdicts& now);

}  // namespace jam::stats
