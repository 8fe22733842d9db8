#pragma once
#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/shown_text.h"

namespace fscil {

// A whole number from `least` that fits T, or an Error naming `origin` and `field`: get<T>()
// would convert 1e300 or -1.5 with undefined behaviour.
template <typename T>
T whole_number(const nlohmann::json& value, const std::string& field, const std::string& origin,
               T least = std::numeric_limits<T>::min()) {
  constexpr auto most = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
  const bool fits = fits_whole_number<T>(value, least);
  if (!fits) {
    throw Error(fmt::format("{}: {} {}, expected a whole number from {} to {}", origin, field,
                            shown_text(value.dump()), least, most));
  }
  return value.get<T>();
}

}  // namespace fscil
