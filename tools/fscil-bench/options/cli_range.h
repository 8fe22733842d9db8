#pragma once
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <string>

#include "core/valid_range.h"

namespace fscil {

// A command-line number checked against the same ranges as --set values, NaN and infinities
// included (CLI11's own PositiveNumber lets NaN through).
inline CLI::Validator within(const ValidRange& valid) {
  return CLI::Validator(
      [valid](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !valid.contains(value)) return "expected a number " + valid.describe();
        return {};
      },
      valid.describe());
}

}  // namespace fscil
