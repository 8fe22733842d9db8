#pragma once
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "metrics/session_accuracy.h"

namespace fscil {

// One epoch of a training stage as the method reported it: a row of the run's training log.
struct EpochLog {
  std::string stage;  // "pretrain", "pseudo-incremental", "projector", "session 3", ...
  int epoch = 0;      // 1-based
  // "loss" (the epoch's mean), its terms, "lr", "seconds" since the session began, and the score
  // an epoch was chosen by where one was measured ("selection_score").
  std::map<std::string, double> values;
};

// No run takes 31 years: a time above this in a result file or checkpoint is damage, not a measurement.
inline constexpr double kMostSeconds = 1e9;

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
  std::vector<EpochLog> training_log;  // RunContext::training_log of this session
};

}  // namespace fscil
