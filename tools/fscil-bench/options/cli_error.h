#pragma once
#include <stdexcept>
#include <string>

namespace fscil {

// Raised for malformed command-line values that CLI11 cannot check by itself.
class CliError : public std::runtime_error {
 public:
  explicit CliError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace fscil
