#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/parameter_set.h"

namespace fscil {

// A setting with named values (an enum, or a bool with a name for each side) read through
// ParameterSet::choice, whose default is `current`, the value the settings struct starts with, so
// a default is written once, in the struct. `names` lists the values in the order an error
// message offers them.
template <typename Value>
Value named_choice(const ParameterSet& params, const std::string& key, Value current,
                   const std::vector<std::pair<std::string, Value>>& names) {
  std::vector<std::string> allowed;
  std::string fallback;
  for (const auto& [name, value] : names) {
    allowed.push_back(name);
    if (value == current) fallback = name;
  }
  const std::string chosen = params.choice(key, fallback, allowed);
  for (const auto& [name, value] : names) {
    if (name == chosen) return value;
  }
  return current;
}

}  // namespace fscil
