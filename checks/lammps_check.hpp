#pragma once
// Cross-check of jam's inertial dynamics against LAMMPS (reference/lammps/compress_inertial.in):
// the same start, Q = 0.1, dt = 0.005, 400 steps of compression at rate 1e-3, in 2D and 3D.
// Compared at the last step:
//   - positions (largest difference, physical units);
//   - LAMMPS's virial pressure and potential energy per atom against jam's, evaluated with
//     LAMMPS's conventions (forces and energy at the box before that step's deformation, volume
//     after it), so that only the integration and the force table can make them differ.
// With `lmp` on the PATH LAMMPS runs; without it the stored LAMMPS result in
// reference/lammps/inertial-<D>d/ is used; with neither the check is skipped, never passed.
#include <string>
#include <vector>

#include "checks/checks.hpp"
#include "checks/verdict.hpp"

namespace jam::checks {

struct LammpsCheckOptions {
  std::string work_directory;                // scratch files
  std::string reference_directory;           // reference/lammps
  bool use_lmp = true;                       // run lmp when available
  bool regenerate = false;                   // rewrite the stored reference from a fresh LAMMPS run
  double margin = default_margin("lammps");  // overdamped comparison: |<Delta p/p>| allowed
};

/// The inertial comparison in 2D and 3D, then the overdamped one (lammps_overdamped_check).
std::vector<Verdict> lammps_check(const LammpsCheckOptions& options);

/// jam's overdamped dynamics against LAMMPS at Q = 0.03 through jamming, 2D and 3D.
std::vector<Verdict> lammps_overdamped_check(const LammpsCheckOptions& options);

}  // namespace jam::checks
