#pragma once
#include <chrono>
#include <cstdint>

namespace fscil {

// Peak resident set size of this process since the last reset_peak_resident() (or its start),
// in bytes.
std::int64_t peak_resident_bytes();
// Starts a new peak from the current resident size, so each run of a multi-run process reports
// its own peak. Without Linux's clear_refs the peak stays process-wide.
void reset_peak_resident();

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
