#pragma once
// What a campaign can decide, before it runs (`jam campaign plan`): for each pooled pressure
// check it will run (finite_size at constant phi and at constant Z, phi_init), whether its
// verdicts can decide at their margins with the planned samples, and what the rest would need.
//
// The variance model: the window scatter s of an ensemble (checks/window_scatter.hpp; the
// runs' scatter of their weighted window mean, which sets sigma_D^2 = s_a^2/n_a + s_b^2/n_b)
// fitted as
//   ln s^2 = c0 + c1 ln N + c2 log10(rate)
// by least squares weighted by degrees of freedom, one fit at constant phi and one at constant
// Z, over the verdicts of judged campaigns (their checks.json): by default the stored result
// of the campaign's dimension (reference/results/reduced-2d or -3d), or a pilot's
// (`--scatter-from DIR`). Its residual scatter is printed as the model's uncertainty. Data of
// one size (a pilot of a one-size design) hold c1 at -1, the self-averaging of a window mean
// over N particles; data of one rate hold c2 at 0; the printed model says which is held.
//
// A verdict is expected to decide when, with no effect present, it passes with probability
// at least 0.8 (checks::kEstimatePower): sigma_D <= M / (z_pass + 1.28).
#include <string>
#include <vector>

#include "campaign/campaign_file.hpp"
#include "campaign/throughput.hpp"

namespace jam {

struct ScatterFit {
  double c0 = 0, c1 = 0, c2 = 0;  // ln s^2 = c0 + c1 ln N + c2 log10 rate
  double residual = 0;            // weighted residual standard deviation of ln s^2
  int points = 0;
  double n_min = 0, n_max = 0, rate_min = 0, rate_max = 0;  // the data's span
  bool n_exponent_held = false;  // one size in the data: c1 = -1 (self-averaging, s^2 ~ 1/N)
  bool rate_slope_held = false;  // one rate in the data: c2 = 0
  bool exact = false;            // as many points as coefficients: no residual estimated
  double scatter(double n, double log10_rate) const;
};

struct ScatterModel {
  ScatterFit at_phi, at_z;
  std::vector<std::string> sources;
};

/// Fits the model to the pooled verdicts of the given checks.json files; throws naming the
/// file when one cannot be read or holds no verdict with window scatter values. `region`
/// "asked" (a campaign that states a range): from a file's verdicts of the range asked where
/// it has them (a pilot judged with the question), its others where it has none, and the
/// sources say which.
ScatterModel fit_scatter_model(const std::vector<std::string>& checks_files,
                               const std::string& region = "");

/// What the verdicts of `jam check` will judge for this campaign, as the plan's "decides"
/// refers to it: the range asked ([question]), the scaling fit's window (3 or more rates), or
/// the whole compression (said as such: no fit and no range asked).
std::string planned_range_words(const Campaign& c);

/// The default sources for a dimension: the stored reduced result's checks.json.
std::vector<std::string> default_scatter_sources(int dim);

/// Prints, after the cost lines of `jam campaign plan`, what each check can decide; `speed`
/// is the measured throughput by size. Returns the number of checks with
/// comparisons the design cannot decide (each printed as a warning line).
int print_decidability(const Campaign& c, const ScatterModel& model, const Throughput& speed);

/// What the phi_init check found in the campaign's directory (DIR/checks.json), if it ran
/// there: per size and rate, the highest phi_init consistent with the lowest and the share of
/// compression time starting there saves. Nothing when there is no checks.json.
void print_phi_init_findings(const Campaign& c);

}  // namespace jam
