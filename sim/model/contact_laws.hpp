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

/// The names of the laws, in the list's order (the first is the default).
inline std::vector<std::string> contact_law_names() {
  return std::apply([](auto... law) { return std::vector<std::string>{decltype(law)::kName...}; },
                    ContactLaws{});
}

/// Calls f.template operator()<Law>() for the law named `name` and returns its result;
/// throws std::invalid_argument for a name not in the list.
template <class F>
auto with_contact_law(std::string_view name, F&& f) {
  using Result = decltype(f.template operator()<std::tuple_element_t<0, ContactLaws>>());
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
      ContactLaws{});
}

}  // namespace jam
