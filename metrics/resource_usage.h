#pragma once
#include <chrono>
#include <cstdint>

namespace fscil {

// Peak resident set size of this process so far, in bytes.
std::int64_t peak_resident_bytes();

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace fscil
