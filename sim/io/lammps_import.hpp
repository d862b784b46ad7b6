#pragma once
// `jam import lammps`: a LAMMPS run of this model (reference/lammps/compress_inertial.in) turned
// into a run file of the simulator's schema, so that statistics, checks and reports work on
// campaigns run with LAMMPS too.
//
// Read from the log: `dimension`, `timestep`, the rate of `fix ... deform ... trate`, and every
// thermo line under a header with the columns Step, Time, c_virial (virial pressure), PotEng
// (energy per atom) and v_Z (contacts per particle). Read from the start's data file: N, the
// box and the species, hence phi_init; phi(t) = phi_init exp(D rate t). Q follows from the mass
// of type 1, m_s = Q^2 (2/D)^2; so the log must be of one run under one isotropic deform
// (lammps_deform.hpp). LAMMPS evaluates its thermo with the forces of the step before
// the box deformation and the volume after it; the pressures are stored as LAMMPS printed them.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace jam {

/// The thermo of a LAMMPS log of this model, with the run's dimension, time step and rate.
struct LammpsThermo {
  int dim = 0;
  double dt = 0, rate = 0;
  std::vector<double> step, time, pressure, energy, contacts;
};

/// Reads a log of reference/lammps/compress_inertial.in; throws with file and line.
LammpsThermo read_lammps_thermo(const std::string& log);

struct LammpsImport {
  std::string log, data, out;  // data: the start of the bundled input (import_lammps_run)
  // Any input (import_lammps_log): the thermo column of each field, and the model.
  std::map<std::string, std::string> columns;
  std::optional<int> dim;
  std::optional<std::int64_t> n, sample;
  std::optional<double> rate, phi_init, diameter_ratio, quality_factor;
  std::string contact = "harmonic";
};

/// The bundled input's log and its start -> a run file of jam's schema (inertial, Q from the
/// masses). Writes atomically; throws with file and line on anything it cannot read.
void import_lammps_run(const LammpsImport& request);

/// The fields `--column FIELD=COLUMN` may name.
const std::vector<std::string>& lammps_import_fields();

/// A log of any input -> an open run (docs/cross-simulator.md). The model's parameters come
/// from the request and from what the log states literally (dimension, fix deform trate, the
/// atoms created or read), which must agree. The packing at each row: the packing_fraction
/// column, else the volume column (N/2 small and N/2 big particles of the diameter ratio), else
/// phi_init exp(D rate t), which needs a log of one run under one fix deform showing its trate;
/// with a volume and a time the box must shrink at the stated rate. Every fix deform of the log
/// must be an isotropic compression at one rate, whichever column gives the packing.
void import_lammps_log(const LammpsImport& request);

}  // namespace jam
