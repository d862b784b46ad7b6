#pragma once
// The checks, declared once: the table below is the only place a check is named. `jam check`'s
// accepted names and help, `run_check` and `all`, `default_margin`, the campaign file's
// [margins] keys, `jam check --list` and the registry written into checks.json (which the
// report reads to know which figure shows which check) are all derived from it.
//
// A new check: its own file (a function of one of the kinds below) and one line in
// JAM_CHECK_TABLE, which names the ensembles its verdicts concern (verdict_ensembles.hpp):
// --until-decided and `campaign plan` then serve it with no further edit.
//
// The table is an X-macro: check_names() expands it in this header, and the campaign library,
// which sits below statistics and checks and includes neither, has its names and `all`
// membership read from it at configure time (campaign/CMakeLists.txt, check_names.hpp.in):
// keep each line X(name, run, margin, unit, reason, in_all, ...) with in_all a literal.
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace jam::checks {

struct StatsData;
struct CheckOptions;
struct RegressionOptions;
struct LammpsCheckOptions;
struct Verdict;
struct Samples;

// What a check reads, one function type per kind:
/// DIR/stats.h5 (the statistical checks).
using StatsCheck = std::vector<Verdict> (*)(const StatsData&, const CheckOptions&);
/// DIR/stats.h5 against a baseline's (`--against`).
using BaselineCheck = std::vector<Verdict> (*)(const StatsData&, const StatsData&,
                                               const CheckOptions&, const RegressionOptions&);
/// LAMMPS's inputs and stored results, and a work directory inside DIR.
using LammpsCheck = std::vector<Verdict> (*)(const LammpsCheckOptions&);
/// Verdicts another check writes with a margin of their own (not run by name).
struct PartOf {
  std::string_view check;
};
using CheckRun = std::variant<StatsCheck, BaselineCheck, LammpsCheck, PartOf>;

/// What a margin measures: a relative pressure difference, or a difference in packing.
enum class MarginUnit { relative, packing_fraction };

// Why each default margin is what it is, in words that stay true when results change: the
// measurements behind them are in docs/statistics-and-checks.md, never in these strings.
namespace margin_reasons {
// The paper treats differences of 1-2% as statistical; at this machine's scale (N <= 2048,
// 10 samples, sample scatter 7-13% at phi 0.84) the checks exclude effects down to 4-8% at the
// fast rates: at 1-2% every verdict of the stored campaigns would be inconclusive.
inline constexpr std::string_view kPressure =
    "what the checks can decide at this machine's scale (N <= 2048, 10 samples: the effects "
    "they exclude at the fast rates, measured in docs/statistics-and-checks.md); the paper's "
    "1-2% would leave every verdict inconclusive";
// The chain check judges the fit window's inverse-variance weighted mean (chain_check.cpp).
inline constexpr std::string_view kChain =
    "the weighted mean Delta p/p over the fit's window, as a fit weighs the points; what the "
    "stored chain controls exclude at every chained rate, and a planted 15% shift failing "
    "every rate, are measured in docs/statistics-and-checks.md#chain";
// The convergence check: the integrator's own error (convergence_check.cpp).
inline constexpr std::string_view kConvergence =
    "the integrator's error must lie well below what the physics checks judge: a tenth of "
    "their 10%, so that a size or start effect at the margin is not the integrator's";
inline constexpr std::string_view kJammingPoint =
    "about the sample spread of phi_Ji at N ~ 10^3; a larger shift of <phi_Ji> would move "
    "phi_J by more than the fit's window steps";
inline constexpr std::string_view kExponents =
    "what the jackknife errors of beta and y at N <= 1024 with 10 samples let such fits decide "
    "(measured in docs/statistics-and-checks.md); the paper's sizes agree within their own "
    "errors";
inline constexpr std::string_view kFitPhiJ =
    "about three jackknife errors of a fitted phi_J at N <= 1024 with 10 samples (measured in "
    "docs/statistics-and-checks.md), and a fifth of the fit's narrowest window (+-0.01)";
// The compare check: two codes of one model (docs/statistics-and-checks.md#compare).
inline constexpr std::string_view kCompare =
    "two codes of one model, protocol and ensemble must give one pressure (jam and LAMMPS on "
    "the same starts: docs/statistics-and-checks.md#compare), so 5% is a difference of the "
    "physics simulated, half the margin of a size or start effect";
inline constexpr std::string_view kLammps =
    "Q = 0.03 reproduces the overdamped limit far within it (measured in "
    "docs/statistics-and-checks.md), so a difference beyond 0.5% is an error of one of the two "
    "codes";
// The isostaticity check: the non-rattlers' contacts when the runs removed their rattlers,
// else every particle's (isostaticity_check.cpp); one margin holds both counts.
inline constexpr std::string_view kIsostatic =
    "the slowest rate's flow adds contacts above the isostatic count, and where the runs kept "
    "their rattlers (no rattlers = true) these hold few contacts at jamming and lower <Z>: a "
    "few percent each, for either count (measured in "
    "docs/statistics-and-checks.md#isostaticity); a count further off is an error of the "
    "contacts or the jamming points, or a rate far from the quasistatic limit";
}  // namespace margin_reasons

// One line per check, in the order `all` runs them and the verdicts are written:
//   X(name, how it runs, default margin, its unit, why, member of `all`, report figure,
//     samples)
// name: `jam check NAME`, the verdicts' `check`, the [margins] key. How it runs: the kind of
// its function, always named `<name>_check` (stats: a StatsCheck, baseline: a BaselineCheck,
// lammps: a LammpsCheck), or part(parent) for verdicts its parent writes; check_registry.cpp
// declares each function from its kind, so a new check's file needs no header. Member of `all`:
// lammps is not (it tests jam against stored LAMMPS results, an installation's test that says
// nothing of a campaign's data and took 18 of a small campaign's 20 passes): `all` judges it only
// when asked (--with-lammps, or [question] checks naming it). Report figure: the stem of the report
// figure that draws the check's verdicts (reports/report_figures*.py), or "verdicts" when only the
// verdict table shows them. Samples: which ensembles its verdicts concern, one of the declarations
// of verdict_ensembles.hpp (samples::). The functions are named only where check_registry.cpp
// expands the table (those other code calls directly are declared again in checks.hpp,
// lammps_check.hpp, regression_check.hpp); check_names() takes the first column alone.
#define JAM_CHECK_TABLE(X)                                                                       \
  X(finite_size, stats, 0.10, relative, kPressure, true, "finite_size", kSizesPlanned)           \
  X(sample_pairs, stats, 0.10, relative, kPressure, true, "sample_pairs", kSizes)                \
  X(phi_init, stats, 0.10, relative, kPressure, true, "jamming_points", kStartsPlanned)          \
  X(jamming_point, part(phi_init), 0.005, packing_fraction, kJammingPoint, true, "verdicts",     \
    kStarts)                                                                                     \
  X(zeta, stats, 0.10, relative, kPressure, true, "verdicts", kRates)                            \
  X(fit_parameters, stats, 0.10, relative, kExponents, true, "verdicts", kFits)                  \
  X(fit_phi_j, part(fit_parameters), 0.002, packing_fraction, kFitPhiJ, true, "verdicts", kFits) \
  X(lammps, lammps, 0.005, relative, kLammps, false, "lammps", kNotBySamples)                    \
  X(regression, baseline, 0.10, relative, kPressure, false, "verdicts", kNotBySamples)           \
  X(chain, baseline, 0.10, relative, kChain, false, "verdicts", kNotBySamples)                   \
  X(convergence, baseline, 0.01, relative, kConvergence, false, "verdicts", kNotBySamples)       \
  X(compare, baseline, 0.05, relative, kCompare, false, "compare", kNotBySamples)                \
  X(compare_jamming, part(compare), 0.005, packing_fraction, kJammingPoint, false, "verdicts",   \
    kNotBySamples)                                                                               \
  X(compare_fit, part(compare), 0.10, relative, kExponents, false, "verdicts", kNotBySamples)    \
  X(compare_fit_phi_j, part(compare), 0.002, packing_fraction, kFitPhiJ, false, "verdicts",      \
    kNotBySamples)                                                                               \
  X(isostaticity, stats, 0.05, relative, kIsostatic, false, "verdicts", kEnsemble)

struct CheckEntry {
  std::string_view name;
  CheckRun run;
  double default_margin;
  MarginUnit margin_unit;
  std::string_view margin_reason;
  bool in_all;  // `jam check all` runs it (a part: its parent writes its verdicts there)
  std::string_view figure;
  // Which ensembles its verdicts concern (verdict_ensembles.hpp): what --until-decided adds
  // samples to and `campaign plan` plans; never null (test_check_registry).
  const Samples* samples;
};

/// Every registered check, in table order.
std::span<const CheckEntry> check_registry();

/// The entry of `name`, or nullptr when no check has that name.
const CheckEntry* find_check(std::string_view name);

/// True for the checks `jam check NAME` runs by name (all but the parts).
bool runs_by_name(const CheckEntry& e);

/// The names `jam check` accepts: the checks that run by name, then "all".
std::vector<std::string> command_names();

/// Every registered name (the campaign file's [margins] keys, which campaign/ reads from the
/// generated campaign/check_names.hpp).
inline std::set<std::string> check_names() {
#define JAM_CHECK_NAME(name, ...) #name,
  return {JAM_CHECK_TABLE(JAM_CHECK_NAME)};
#undef JAM_CHECK_NAME
}

/// The registry as a JSON text: an array of {name, runs (stats, baseline, lammps or the
/// check that writes it), default_margin, margin_unit, margin_reason, in_all, figure}; what
/// `jam check --list --json` prints and checks.json carries under "checks".
std::string registry_json();

/// The registry as a table for a terminal (`jam check --list`).
std::string registry_table();

}  // namespace jam::checks
