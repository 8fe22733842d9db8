#pragma once
#include <CLI/CLI.hpp>

#include <string>

#include "core/valid_range.h"
#include "core/number_text.h"

namespace fscil {

// A command-line number checked against the same ranges as --set values, NaN and infinities
// included (CLI11's own PositiveNumber lets NaN through).
inline CLI::Validator within(const ValidRange& valid) {
  return CLI::Validator(
      [valid](std::string& text) -> std::string {
        const auto value = parse_number<double>(text);
        if (!value || !valid.contains(*value)) return "expected a number " + valid.describe();
        return {};
      },
      valid.describe());
}

// A path or text option whose empty value means nothing: `refusal` says what to give instead.
inline CLI::Validator refusing_empty(const std::string& refusal) {
  return CLI::Validator([refusal](std::string& text) { return text.empty() ? refusal : std::string(); }, "");
}

}  // namespace fscil
