#include "app/check_options.hpp"

#include <type_traits>
#include <variant>

namespace jam {

void add_judging_options(CLI::App* command, design::JudgingArgs& args) {
  for (const auto& o : design::judging_options()) {
    std::visit(
        [&](auto field) {
          auto& value = args.*field;
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, bool>) {
            command->add_flag(o.flag, value, o.help);
          } else if constexpr (requires { value.has_value(); }) {
            command->add_option(o.flag, value, o.help)->always_capture_default(false);
          } else {
            command->add_option(o.flag, value, o.help)->capture_default_str();
          }
        },
        o.field);
  }
}

}  // namespace jam
