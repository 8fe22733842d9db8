#pragma once
#include <vector>

#include "metrics/session_outcome.h"

namespace fscil {

// A session result's scalar fields, listed once: result files and checkpoints store each under
// its `key` (metrics/session_json.h), the tidy CSV under its `column` (reports/tidy_sessions.cpp).
struct SessionField {
  enum class Kind {
    count,          // a whole number that fits an int
    samples,        // a whole number that fits an int64
    percent,        // in [0, 100]
    novel_percent,  // in [0, 100]; the tidy CSV leaves it empty in the base session, which has no novel classes
    seconds,
    ratio,          // NaN when unknown (no acquisition contexts)
  };
  const char* key;
  const char* column;  // nullptr: not a column of the tidy CSV
  Kind kind;
  double (*value)(const SessionOutcome&);
  void (*set)(SessionOutcome&, double);
};

// In the tidy CSV's column order.
const std::vector<SessionField>& session_fields();

}  // namespace fscil
