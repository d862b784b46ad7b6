#pragma once
// Running a check by name on a campaign directory (`jam check NAME DIR`): the registry's
// entry says what the check reads (checks/check_registry.hpp), this gives it that.
#include <string>
#include <vector>

#include "checks/check_registry.hpp"
#include "checks/checks.hpp"
#include "checks/lammps_check.hpp"
#include "checks/regression_check.hpp"

namespace jam::checks {

/// Everything a check may read. Each check takes only what its kind needs, so that
/// `jam check lammps DIR` runs without a stats.h5 and stats.h5 is read once for `all`.
struct CheckInputs {
  std::string directory;  // the campaign directory: its stats.h5
  CheckOptions options;
  std::string baseline_directory;  // a baseline check's --against (a directory with stats.h5)
  RegressionOptions regression;
  LammpsCheckOptions lammps;  // its margin is set from options.margin(name)
  // The campaign's runs are not jam's (an external campaign, campaign/external_campaign.hpp):
  // `all` leaves out the checks of jam's own simulator against LAMMPS, which say nothing of them.
  bool runs_of_another_simulator = false;
};

/// The verdicts of the check `name` ("all": every member of `all`, in table order). Throws
/// std::invalid_argument for a name that does not run by name, std::runtime_error when an
/// input the check needs is missing.
std::vector<Verdict> run_checks(const std::string& name, const CheckInputs& in);

}  // namespace jam::checks
