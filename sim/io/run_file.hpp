#pragma once
// The run file: one HDF5 file per compression run. Schema (documented in reference/schema.md):
// root attributes describe the run, 1-D datasets hold one entry per output point.
#include <string>
#include <vector>

#include "sim/observables/observables.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {

/// Attributes that the run determines (beyond the configuration).
struct RunMetadata {
  std::int64_t n = 0;
  double phi_init = 0.0;
  double initial_box_length = 0.0;
  std::string integrator;
  std::string initial_configuration;  // "random" or the data file read
  std::int64_t steps = 0;
  std::int64_t relax_steps = 0;
  bool relax_converged = true;
  double jamming_packing_fraction = 0.0;  // NaN when not bracketed; written only when asked for
  std::int64_t jamming_minimizations = 0;
};

/// Why the run file at path cannot be used, or "" when it is sound: unreadable HDF5, not
/// complete, datasets of unequal length, a data checksum (attribute data_checksum, FNV-1a of the
/// datasets) that does not match, or a packing fraction that is not finite and increasing.
std::string run_file_problem(const std::string& path);

/// Writes path atomically (HDF5 to "<path>.partial", renamed when closed).
template <int D>
void write_run_file(const std::string& path, const SimConfig& config, const RunMetadata& meta,
                    const std::vector<Observables<D>>& points);

}  // namespace jam
