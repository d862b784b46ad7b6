#pragma once
// The list of contact laws: a new law is its header (contact_law.hpp says what it provides)
// plus one entry here. Run-time names (--contact, the campaign key `contact`, the run-file
// attribute) are dispatched once, to a template instantiation, by with_contact_law().
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "sim/model/harmonic_contact.hpp"
#include "sim/model/hertzian_contact.hpp"

namespace jam {

using ContactLaws = std::tuple<HarmonicContact, HertzianContact>;

/// The names of the laws, in the list's order (the first is the default). Laws: the list, by
/// default this one (a test may pass a longer list: tests/open_run_registry_tool.cpp).
template <class Laws = ContactLaws>
std::vector<std::string> contact_law_names() {
  return std::apply([](auto... law) { return std::vector<std::string>{decltype(law)::kName...}; },
                    Laws{});
}

/// --contact's help: the laws of the list joined as the one-line errors list allowed values, so
/// that a new law's line names it there too. The default is the list's first (the paper's).
template <class Laws = ContactLaws>
std::string contact_law_help() {
  const std::vector<std::string> names = contact_law_names<Laws>();
  std::string out = "Contact law: ";
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return out + " (default " + names.front() + ", the paper's)";
}

/// Calls f.template operator()<Law>() for the law of Laws named `name` and returns its result;
/// throws std::invalid_argument for a name not in the list.
template <class Laws = ContactLaws, class F>
auto with_contact_law(std::string_view name, F&& f) {
  using Result = decltype(f.template operator()<std::tuple_element_t<0, Laws>>());
  return std::apply(
      [&](auto... law) {
        std::optional<Result> r;
        (void)((name == decltype(law)::kName
                    ? (r.emplace(f.template operator()<decltype(law)>()), true)
                    : false) ||
               ...);
        if (!r) throw std::invalid_argument("unknown contact law " + std::string(name));
        return std::move(*r);
      },
      Laws{});
}

}  // namespace jam
