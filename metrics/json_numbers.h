#pragma once
#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>

#include "core/error.h"
#include "core/shown_text.h"

namespace fscil {

// A whole number from `least` that fits T, or an Error naming `origin` and `field`: get<T>()
// would convert 1e300 or -1.5 with undefined behaviour.
template <typename T>
T whole_number(const nlohmann::json& value, const std::string& field, const std::string& origin,
               T least = std::numeric_limits<T>::min()) {
  constexpr auto most = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
  const auto from_least = [least](std::uint64_t number) {
    if constexpr (std::is_signed_v<T>) {
      if (least < 0) return true;
    }
    return number >= static_cast<std::uint64_t>(least);
  };
  bool fits = false;
  if (value.is_number_unsigned()) {
    const auto number = value.get<std::uint64_t>();
    fits = number <= most && from_least(number);
  } else if (value.is_number_integer()) {
    const auto number = value.get<std::int64_t>();
    fits = number < 0 ? std::is_signed_v<T> && number >= static_cast<std::int64_t>(least)
                      : static_cast<std::uint64_t>(number) <= most && from_least(static_cast<std::uint64_t>(number));
  }
  if (!fits) {
    throw Error(fmt::format("{}: {} {}, expected a whole number from {} to {}", origin, field,
                            shown_text(value.dump()), least, most));
  }
  return value.get<T>();
}

}  // namespace fscil
