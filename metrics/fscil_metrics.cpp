#include "metrics/fscil_metrics.h"

#include <numeric>
#include <stdexcept>

namespace fscil {

FscilSummary summarize_sessions(const std::vector<double>& accuracy) {
  if (accuracy.empty()) throw std::invalid_argument("no session accuracies to summarise");
  FscilSummary summary;
  summary.average_accuracy = std::accumulate(accuracy.begin(), accuracy.end(), 0.0) / accuracy.size();
  summary.performance_drop = accuracy.front() - accuracy.back();
  const std::size_t steps = accuracy.size() - 1;
  if (steps == 0) return summary;
  double rate = 0;
  for (std::size_t l = 0; l < steps; ++l) {
    // A session at 0% accuracy has no relative drop to measure; it contributes nothing.
    if (accuracy[l] > 0) rate += (accuracy[l] - accuracy[l + 1]) / accuracy[l];
  }
  summary.average_drop_rate = 100.0 * rate / static_cast<double>(steps);
  return summary;
}

}  // namespace fscil
