#pragma once
// Refuses time steps beyond the linear stability bound of the integrator on the current
// contact network (see sim/dynamics/stability.hpp), checked every kStabilityCheckInterval steps
// of relaxation and compression. A moderately too large dt does not blow up: the one-sided
// contacts open before the unstable modes grow, and the run finishes with too few contacts
// and a wrong pressure. So waiting for non-finite numbers is not enough; this measures the
// stiffness instead.
//
// The bound is dt lambda_max < 2 for all three integrators (Euler and Heun: the rate lambda of
// the stiffest overdamped mode; Verlet: its angular frequency, plus the drag bound
// dt < 2 m_s/gamma_s checked in validate()). A run is refused once dt lambda_max exceeds
// kStabilityLimit. Cost: one pass over the neighbor list (a Gershgorin bound) every check, and
// a power iteration only when that bound is within reach of the limit.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/dynamics/stability.hpp"
#include "sim/run/sim_config.hpp"

namespace jam {

/// dt lambda_max above which a run is refused (the linear limit is 2; see
/// docs/stability-and-faults.md).
inline constexpr double kStabilityLimit = 1.9;
/// Steps between checks: an unstable run is stopped within this many steps of the contact
/// network becoming too stiff.
inline constexpr long long kStabilityCheckInterval = 256;

/// The time step was beyond the stability bound of the integrator.
struct StabilityError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <int D>
class StabilityGuard {
 public:
  StabilityGuard(const SimConfig& c, const Species<D>& species)
      : dt_(c.dt), integrator_(c.resolved_integrator()), inertial_(c.dynamics == "inertial") {
    inertia_ = inertial_ ? species.masses(c.quality_factor) : species.drag;
  }

  /// Stiffness of the current contacts: lambda_max for overdamped dynamics (a rate), omega_max
  /// for inertial dynamics (sqrt of the eigenvalue of M^-1 H). Valid list required.
  template <class Contact>
  double stiffest(System<D, Contact>& sys, double box_length, bool exact) const {
    const double bound = exact ? stiffest_mode(sys, box_length, inertia_)
                               : stiffest_mode_bound(sys, box_length, inertia_);
    return inertial_ ? std::sqrt(bound) : bound;
  }

  /// Throws StabilityError when dt times the stiffest mode exceeds kStabilityLimit.
  /// `stage` says where, e.g. "relaxation" or "compression".
  template <class Contact>
  void check(System<D, Contact>& sys, double box_length, double packing_fraction,
             const char* stage) {
    sys.update_neighbors(box_length);
    if (dt_ * stiffest(sys, box_length, false) <= kStabilityLimit) return;  // cheap bound
    const double lambda = stiffest(sys, box_length, true);
    worst_ = std::max(worst_, dt_ * lambda);
    if (!(dt_ * lambda <= kStabilityLimit)) {
      throw StabilityError(fmt::format(
          "--dt {:g}: unstable for {} ({} at phi {:.4f}): the stiffest contact mode has {} = "
          "{:.4g}, so dt must be below {:.2g}/{} = {:.3g} (estimated safe bound; see "
          "docs/stability-and-faults.md)",
          dt_, integrator_, stage, packing_fraction, inertial_ ? "omega_max" : "lambda_max", lambda,
          kStabilityLimit, inertial_ ? "omega_max" : "lambda_max", kStabilityLimit / lambda));
    }
  }

  /// Largest dt lambda_max measured by a power iteration so far (0 if none was needed).
  double worst() const { return worst_; }

 private:
  double dt_;
  std::string integrator_;
  bool inertial_;
  ModeInertia inertia_{};
  double worst_ = 0.0;
};

}  // namespace jam
