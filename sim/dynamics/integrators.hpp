#pragma once
// The integrator classes as one type list, in the order of the integrator list
// (integrator_list.hpp): a run dispatches its --integrator name to a class here, once
// (with_integrator), and the typed tests run over the list. A new integrator is its header,
// an entry in kIntegrators and an entry here; the static_assert below keeps the two in step.
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

#include "sim/dynamics/inertial_verlet.hpp"
#include "sim/dynamics/integrator_list.hpp"
#include "sim/dynamics/overdamped_chebyshev.hpp"
#include "sim/dynamics/overdamped_euler.hpp"
#include "sim/dynamics/overdamped_heun.hpp"
#include "sim/dynamics/stepper_state.hpp"

namespace jam {

template <int D>
using Integrators =
    std::tuple<OverdampedEuler<D>, OverdampedHeun<D>, OverdampedChebyshev<D>, InertialVerlet<D>>;

namespace detail {
template <class Tuple, std::size_t... K>
constexpr bool names_match(std::index_sequence<K...>) {
  return std::tuple_size_v<Tuple> == kIntegrators.size() &&
         ((std::string_view(std::tuple_element_t<K, Tuple>::kName) == kIntegrators[K].name) && ...);
}
}  // namespace detail
static_assert(detail::names_match<Integrators<2>>(std::make_index_sequence<kIntegrators.size()>{}),
              "Integrators<D> and kIntegrators must list the same integrators in the same order");

/// Whether a stepper chooses its own steps (step(sys, t, h_max) returns the step taken).
template <class Stepper>
constexpr bool is_adaptive() {
  if constexpr (requires { Stepper::kAdaptive; }) {
    return Stepper::kAdaptive;
  } else {
    return false;
  }
}

/// Calls f(stepper) with a stepper of the integrator named `name` for n particles and returns
/// its result; throws std::invalid_argument for a name not in the list.
template <int D, class F>
auto with_integrator(std::string_view name, std::size_t n, const StepperOptions& o, F&& f) {
  using First = std::tuple_element_t<0, Integrators<D>>;
  using Result = decltype(f(std::declval<First&>()));
  auto each = [&]<class... S>(std::type_identity<std::tuple<S...>>) {
    std::optional<Result> r;
    (void)((name == S::kName ? (
                                   [&] {
                                     S stepper(n, o);
                                     r.emplace(f(stepper));
                                   }(),
                                   true)
                             : false) ||
           ...);
    if (!r) throw std::invalid_argument("unknown integrator " + std::string(name));
    return std::move(*r);
  };
  return each(std::type_identity<Integrators<D>>{});
}

}  // namespace jam
