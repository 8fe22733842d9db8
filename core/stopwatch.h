#pragma once
#include <chrono>

namespace fscil {

// Wall-clock seconds since construction, on the steady clock.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  // One that reads `seconds` already: a stage taken over from another run keeps its time.
  static Stopwatch started_seconds_ago(double seconds) {
    Stopwatch clock;
    clock.start_ -= std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
    return clock;
  }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace fscil
