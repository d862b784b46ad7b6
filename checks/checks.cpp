// The checks by name, and their default margins.
#include "checks/checks.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace jam::checks {

double default_margin(const std::string& check) {
  // Relative pressure differences. The paper treats differences of 1-2% as statistical; at the
  // scale of this machine's campaigns (N <= 2048, 10 samples, a sample-to-sample scatter of
  // 7-13% at phi 0.84) the checks exclude effects down to about X% (measured: docs/
  // statistics-and-checks.md), so the default margin is what they can decide.
  if (check == "finite_size" || check == "sample_pairs" || check == "phi_init" ||
      check == "regression")
    return 0.10;
  // <phi_Ji> differences, in packing fraction.
  if (check == "jamming_point") return 0.005;
  // jam against LAMMPS at Q = 0.03 through jamming (the overdamped comparison): 0.5%. Q = 0.03
  // reproduces the overdamped limit to about 0.01% (docs/performance.md), so a difference
  // beyond 0.5% is an error of one of the two codes; 4 samples exclude differences down to
  // 0.05-0.07% (the stored results).
  if (check == "lammps") return 0.005;
  throw std::invalid_argument(fmt::format("check '{}': no margin defined", check));
}

std::vector<Verdict> run_check(const std::string& name, const StatsData& d, const CheckOptions& o) {
  if (name == "finite_size") return finite_size_check(d, o);
  if (name == "sample_pairs") return sample_pairs_check(d, o);
  if (name == "phi_init") return phi_init_check(d, o);
  if (name == "all") {
    std::vector<Verdict> all;
    for (auto* check : {&finite_size_check, &sample_pairs_check, &phi_init_check}) {
      const auto v = check(d, o);
      all.insert(all.end(), v.begin(), v.end());
    }
    return all;
  }
  throw std::invalid_argument(
      fmt::format("check '{}': unknown (finite_size, sample_pairs, phi_init, all)", name));
}

}  // namespace jam::checks
