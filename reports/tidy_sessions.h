#pragma once
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// Tidy per-session CSV for pandas or R: one line per (method, dataset, sweep cell, selection,
// seed, session), with a column per sweep key. Accuracy on all seen classes, on the base and the
// novel classes and the current session's classes, the harmonic mean of base and novel, train and
// test seconds and the context-to-class dispersion R (empty when unknown); novel, current and
// harmonic mean are empty in session 0.
std::string render_tidy_sessions_csv(const std::vector<RunRecord>& records);

}  // namespace fscil
