#pragma once
#include <limits>
#include <map>
#include <string>

#include "metrics/session_accuracy.h"

namespace fscil {

// What the runner measured after one session.
struct SessionOutcome {
  int session = 0;
  int seen_classes = 0;
  SessionAccuracy accuracy;
  double train_seconds = 0;  // train_base or learn_session
  double test_seconds = 0;
  // Context-to-class dispersion R of the test embeddings of the seen classes (mean and max over
  // classes); NaN when the dataset carries no acquisition contexts.
  double context_ratio_mean = std::numeric_limits<double>::quiet_NaN();
  double context_ratio_max = std::numeric_limits<double>::quiet_NaN();
  // What the method reported while it trained this session (RunContext::diagnostics).
  std::map<std::string, double> diagnostics;
};

}  // namespace fscil
