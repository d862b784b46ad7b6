#pragma once
// What the checks read: the per-sample tables of DIR/stats.h5 (never the runs themselves).
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace jam::checks {

struct EnsembleTables {
  std::string name;
  std::int64_t n = 0;
  double phi_init = 0, log10_rate = 0;
  std::vector<double> phi_grid;
  std::vector<std::vector<double>> pressure_at_phi;  // [sample][point]
  std::vector<std::int64_t> sample_ids;              // campaign sample number of each row
  std::vector<double> z_grid;
  std::vector<std::vector<double>> pressure_at_z;  // empty when no constant-Z average
  std::vector<double> phi_at_z;                    // mean packing at each Z (empty when not stored)
  std::vector<double> jamming_points;  // phi_Ji per sample (NaN: not found); empty if not sought
  std::vector<std::int64_t> jamming_sample_ids;  // the sample of each jamming point (same order)
  // <Z> at each packing of phi_grid: the mean over the samples of the contacts per particle
  // (constant_phi/contacts_per_particle_samples; NaN where no sample has one); empty when the
  // runs stored no contacts. Where it crosses isostaticity places the regions when nothing
  // else gives phi_J (checks/regions.hpp).
  std::vector<double> z_at_phi;
  // ... and per sample, the rows of sample_ids ([sample][point]; empty likewise): what a check
  // of the contacts of each run reads (isostaticity_check.cpp).
  std::vector<std::vector<double>> z_samples_at_phi;
  // ... and with rattlers removed (constant_phi/contacts_per_particle_no_rattlers_samples,
  // stored when every run was made with rattlers = true; empty otherwise).
  std::vector<std::vector<double>> z_nr_samples_at_phi;
  // Where the compression, not the start, sets the pressure (margin.hpp,
  // first_compression_point): the packing, and the mean Z there. Comparisons start here.
  double compressed_from_phi = 0, compressed_from_z = 0;
  // phi'_init of a chained rate (0: a relaxed start): the start carries the faster rate's
  // pressure, and the transient is its decay (margin.hpp, first_chained_compression_point).
  double chain_phi_init = 0;
  // What each run covers (stats.h5 coverage/, stats/run_coverage.hpp; empty in files written
  // before it), for the compare check: the median spacing of each row's output packings, and
  // the tables again over the grid any run reaches (NaN beyond a run's end) where that grid is
  // longer than the common one above.
  struct Coverage {
    std::vector<double> output_step;  // [sample]
    std::vector<double> phi_grid;
    std::vector<std::vector<double>> pressure_at_phi;
    std::vector<double> z_grid;
    std::vector<std::vector<double>> pressure_at_z;
    std::vector<double> phi_at_z;  // mean over the runs that reach each Z
  } coverage;
};

/// An ensemble's identity across campaigns: size, phi_init, log10 rate.
using EnsembleKey = std::tuple<std::int64_t, double, double>;
inline EnsembleKey ensemble_key(const EnsembleTables& e) {
  return {e.n, e.phi_init, e.log10_rate};
}

/// The ensemble as verdicts name it: "n<N> phi_init <phi> rate 1e<log10 rate>".
std::string case_label(const EnsembleTables& e);

/// The scaling fit of one (N, phi_init) at the representative fit's window (stats.h5
/// fit/families): jackknife estimates and errors, or why there is none.
struct FamilyParameters {
  std::int64_t n = 0;
  double phi_init = 0;
  double phi_j = NAN, phi_j_err = NAN, beta = NAN, beta_err = NAN, y = NAN, y_err = NAN;
  std::int64_t samples = 0;
  std::string failure;  // non-empty: no fit
  // The fit's own quality test (stats.h5 `quality`, `quality_reason`; "ok" when not stored).
  std::string quality = "ok", quality_reason;
};

struct StatsData {
  std::string directory;  // where it was read from (empty: made in memory)
  std::string campaign;
  int dim = 2;
  bool pooled = false;
  // The edges of the scaling fit's window (stats.h5 fit/representative phi_min, phi_max), when
  // `jam stats` fitted: the data the fit uses.
  std::optional<double> fit_window_min, fit_window_max;
  // ... and those of the constant-Z fit (fit_z/representative), a window in packing too.
  std::optional<double> fit_z_window_min, fit_z_window_max;
  // ... and its phi_J (the zeta check compares below it).
  std::optional<double> fit_phi_j;
  std::vector<EnsembleTables> ensembles;
  std::vector<FamilyParameters> families;  // empty when stats.h5 has none
};

/// Sets e.compressed_from_phi and e.compressed_from_z from e's pressure at constant phi and its
/// contacts per particle there ([sample][point], empty when unknown: then Z is not limited).
void find_compressed_range(EnsembleTables& e, const std::vector<std::vector<double>>& z_at_phi);

/// Reads DIR/stats.h5; throws with a message to run `jam stats DIR` when it is missing.
StatsData read_stats(const std::string& directory);

/// Rows of two tables restricted to the grid values both grids have (multiples of a step).
struct Aligned {
  std::vector<double> grid;
  std::vector<std::vector<double>> a, b;
};
Aligned align(const std::vector<double>& grid_a, const std::vector<std::vector<double>>& a,
              const std::vector<double>& grid_b, const std::vector<std::vector<double>>& b,
              double grid_min = -1e300, double grid_max = 1e300);

}  // namespace jam::checks
