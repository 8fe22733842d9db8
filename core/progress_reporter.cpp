#include "core/progress_reporter.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

namespace fscil {

void ProgressReporter::stage(const std::string& what) {
  stage_clock_ = Stopwatch();
  if (out_ != nullptr) fmt::print(*out_, "[fscil-bench] {}\n", what);
}

void ProgressReporter::epoch(const std::string& phase, int epoch, int epochs, double loss) {
  if (out_ == nullptr) return;
  const double elapsed = stage_clock_.seconds();
  const double eta = epoch > 0 ? elapsed / epoch * (epochs - epoch) : 0.0;
  fmt::print(*out_, "[fscil-bench]   {} epoch {}/{} loss {:.4f} elapsed {:.0f}s ETA {:.0f}s\n", phase, epoch, epochs,
             loss, elapsed, eta);
  out_->flush();
}

void ProgressReporter::note(const std::string& message) {
  if (out_ != nullptr) fmt::print(*out_, "[fscil-bench]   {}\n", message);
}

}  // namespace fscil
