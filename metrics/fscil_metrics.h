#pragma once
#include <vector>

namespace fscil {

// The paper's summary of per-session accuracies (percent), PROTOCOLS.md:
// AA = mean accuracy, PD = Acc_0 - Acc_S, ADR = 100/S * sum_l (Acc_l - Acc_{l+1}) / Acc_l.
struct FscilSummary {
  double average_accuracy = 0;
  double performance_drop = 0;
  double average_drop_rate = 0;
};

FscilSummary summarize_sessions(const std::vector<double>& session_accuracy);

}  // namespace fscil
