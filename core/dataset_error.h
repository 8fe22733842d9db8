#pragma once
#include <stdexcept>
#include <string>

namespace fscil {

// Raised for every bad dataset input: missing or malformed files, wrong shapes, bad values.
// The message names the file (and field) and what was expected.
class DatasetError : public std::runtime_error {
 public:
  explicit DatasetError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace fscil
