#pragma once
// The open run format as data: what `jam validate`, `jam import` and `jam campaign import`
// enforce, written out by `jam schema open-run` as reference/schema/open_run.toml, the file
// jamio validates with. The names come from the binary's own registries, never from a second
// list: the contact laws from ContactLaws (sim/model/contact_laws.hpp), the dynamics and
// integrators from kIntegrators (sim/dynamics/integrator_list.hpp); the numbers from
// kOpenRunLimits (open_run_limits.hpp), the series from kOpenRunSeries (open_run.hpp).
#include <string>
#include <vector>

#include "sim/model/contact_laws.hpp"

namespace jam {

struct OpenRunSchema {
  std::vector<std::string> contacts;  // the contact laws' names, the first the default
  std::vector<std::string> formulas;  // each law's U(r), in words
};

/// The schema of a list of contact laws (a std::tuple of laws, contact_law.hpp).
template <class Laws>
OpenRunSchema open_run_schema_of() {
  return std::apply(
      [](auto... law) {
        return OpenRunSchema{{decltype(law)::kName...}, {decltype(law)::kFormula...}};
      },
      Laws{});
}

/// The binary's own: the laws of ContactLaws.
const OpenRunSchema& open_run_schema();

/// The schema as TOML (reference/schema/open_run.toml): every attribute and dataset of an open
/// run and of a frames file with its type, shape, units and allowed values, the limits with
/// their reasons, the contact laws and integrators.
std::string open_run_schema_toml(const OpenRunSchema& schema = open_run_schema());

}  // namespace jam
