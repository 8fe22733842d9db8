#pragma once
#include <stdexcept>
#include <string>

namespace fscil {

// Raised for bad protocol set-ups: impossible session plans, malformed parameters, too few samples.
class ProtocolError : public std::runtime_error {
 public:
  explicit ProtocolError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace fscil
