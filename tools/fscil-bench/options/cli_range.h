#pragma once
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <string>

#include "core/error.h"
#include "core/valid_range.h"
#include "core/number_text.h"
#include "core/shown_text.h"

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

// A named choice read by its floor's own reader (`read` throws fscil::Error, "split mode 'X':
// expected recording or segment"): the refusal is the value typed and what the reader expected
// ("'X': expected recording or segment"), which the command line puts after the option's name; a
// reader's line that names the option itself ("--methods a,: an empty name ...") as it is.
inline CLI::Validator read_by(void (*read)(const std::string&)) {
  return CLI::Validator(
      [read](std::string& text) -> std::string {
        try {
          read(text);
        } catch (const Error& error) {
          const std::string message = error.what();
          if (message.rfind("--", 0) == 0) return message;
          const auto expected = message.find("': expected ");
          return fmt::format("'{}': {}", shown_text(text),
                             expected == std::string::npos ? message : message.substr(expected + 3));
        }
        return {};
      },
      "");
}

}  // namespace fscil
