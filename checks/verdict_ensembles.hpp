#pragma once
// Which ensembles a check's verdicts concern, declared in the check's registry line
// (check_registry.hpp, column "samples"): what `campaign run --until-decided` adds samples to,
// how it recognises a verdict from one look to the next, and what `campaign plan` says each
// design can decide. Neither names a check: a new check is served by naming one of these
// declarations in its line (or a new one written here), and a line without one does not
// compile (the table's column count) and is refused by test_check_registry if null.
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "campaign/added_samples.hpp"
#include "campaign/campaign_file.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

using Values = std::map<std::string, double>;  // a verdict's `values`

struct Samples {
  /// The ensembles more samples of which would help decide a verdict with these values:
  /// the first set first (its values `samples_needed_a`), then the second; empty when more
  /// samples of this campaign cannot decide it.
  std::vector<EnsembleId> (*ensembles)(const Values&);
  /// The `values` keys that name what a verdict compares, in this order: every key its check
  /// writes that tells two of its verdicts apart. With its check and region they identify it
  /// across looks (verdict_identity: its case name names the fit window, which moves as
  /// samples are added); the order is that of the states until-decided has written.
  std::span<const std::string_view> identity;
  /// The comparisons the check will make for a design, as the values its verdicts will
  /// carry (`constant_z` 1: at constant Z); empty: the planner plans none for it.
  std::vector<Values> (*planned)(const Campaign&);
};

namespace samples {
/// Two sizes, n_a against n_b, at phi_init and log10_rate (finite_size): planned for the
/// smallest size against the largest at every phi_init and rate, at constant phi and Z.
extern const Samples kSizesPlanned;
/// The same pairs, not planned (sample_pairs).
extern const Samples kSizes;
/// Two starts of size n: phi_init against lowest_phi_init at log10_rate (phi_init): planned
/// for every phi_init above the lowest at every size and rate.
extern const Samples kStartsPlanned;
/// The same pairs, not planned (jamming_point, written with phi_init).
extern const Samples kStarts;
/// Two rates of size n at phi_init: log10_rate_slow against log10_rate_faster (zeta).
extern const Samples kRates;
/// One ensemble, n at phi_init and log10_rate, judged against a value the model states (not
/// against another ensemble), not planned: the planner's variance model is of pressure
/// differences between two ensembles (isostaticity).
extern const Samples kEnsemble;
/// Fitted families (n_a, phi_init_a) against (n_b, phi_init_b): a fit's verdict, which the samples
/// of no single pair of ensembles decide (fit_parameters, fit_phi_j).
extern const Samples kFits;
/// Verdicts more samples of this campaign cannot decide: another campaign's (regression,
/// chain, convergence, compare), LAMMPS's (lammps).
extern const Samples kNotBySamples;
}  // namespace samples

/// What the verdict's check declares of its verdicts (its registry line); throws
/// std::logic_error for a verdict of a check the registry does not hold.
const Samples& samples_of(const Verdict& v);

/// A verdict's identity across looks: "CHECK[ region=R] key=value ...", its region (none for
/// "pooled": a pooled verdict and its regions compare the same sets, and states written before
/// regions name none) and the values of its declaration's identity, in their order.
std::string verdict_identity(const Verdict& v);

}  // namespace jam::checks
