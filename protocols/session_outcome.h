#pragma once
#include "metrics/session_accuracy.h"

namespace fscil {

// What the runner measured after one session.
struct SessionOutcome {
  int session = 0;
  int seen_classes = 0;
  SessionAccuracy accuracy;
  double train_seconds = 0;  // train_base or learn_session
  double test_seconds = 0;
};

}  // namespace fscil
