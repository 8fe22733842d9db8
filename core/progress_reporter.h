#pragma once
#include <ostream>
#include <string>

#include "core/stopwatch.h"

namespace fscil {

// Progress of long work on stderr: what runs, epochs with loss and ETA. Silent when quiet.
class ProgressReporter {
 public:
  explicit ProgressReporter(std::ostream* out) : out_(out) {}
  static ProgressReporter quiet() { return ProgressReporter(nullptr); }

  // A new stage, e.g. "prototype seed 1 | session 0 (base, 75 classes)".
  void stage(const std::string& what);
  // One finished epoch of `epochs` in the current stage.
  void epoch(const std::string& phase, int epoch, int epochs, double loss);
  void note(const std::string& message);

 private:
  std::ostream* out_;
  Stopwatch stage_clock_;
};

}  // namespace fscil
