#pragma once
// The run file: one HDF5 file per compression run. Schema (documented in reference/schema.md):
// root attributes describe the run, 1-D datasets hold one entry per output point.
#include <optional>
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
  std::int64_t force_evaluations = 0;  // the compression's (RunState::force_evaluations)
  std::int64_t relax_steps = 0;
  bool relax_converged = true;
  double jamming_packing_fraction = 0.0;  // NaN when not bracketed; written only when asked for
  std::int64_t jamming_minimizations = 0;
};

/// Run files of schema 2 store schema_version = 2, the run's fingerprint (its parameters, as
/// sim_config.hpp's fingerprint()) and a checksum over every attribute and dataset
/// (content_checksum.hpp). Schema 1 files (no schema_version) checksummed only the datasets.
constexpr int kRunFileSchemaVersion = 2;

/// The root attribute "units" of a run file; each dataset carries its own "units" too.
constexpr const char* kRunFileUnits =
    "the paper's units: lengths d_s (small diameter), energies k_e (contact stiffness), times "
    "t0 = (D/2) k_d V_s d_s^2 / k_e; pressure and stress k_e/d_s^D, compression_rate 1/t0, dt t0";

struct RunFileCheck {
  std::string problem;    // "" when the file is sound
  bool verified = false;  // its checksum covers every attribute (schema 2)
};

/// Whether the run file at path can be used: unreadable HDF5, not complete, no or a wrong
/// checksum, datasets of unequal length, or a packing fraction that is not finite and
/// increasing make it unusable. A sound schema-1 file is usable but not verified.
RunFileCheck check_run_file(const std::string& path);

/// check_run_file(path).problem.
std::string run_file_problem(const std::string& path);

/// "" when the run file at path was written by the run `planned` describes (its stored
/// fingerprint equals fingerprint(planned); for schema-1 files, which have none, the stored
/// parameter attributes are compared one by one); otherwise which parameters differ.
std::string run_identity_problem(const std::string& path, const SimConfig& planned);

/// The fingerprint the run file at path stores (schema 2; nullopt: none, or unreadable).
std::optional<std::string> stored_fingerprint(const std::string& path);

/// Writes path atomically (HDF5 to "<path>.partial", renamed when closed).
template <int D>
void write_run_file(const std::string& path, const SimConfig& config, const RunMetadata& meta,
                    const std::vector<Observables<D>>& points);

}  // namespace jam
