#pragma once
#include <stdexcept>
#include <string>

namespace fscil {

// Raised for unreadable or inconsistent result files and unwritable reports.
class ReportError : public std::runtime_error {
 public:
  explicit ReportError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace fscil
