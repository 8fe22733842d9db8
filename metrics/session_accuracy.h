#pragma once
#include <cstdint>
#include <vector>

namespace fscil {

// Accuracy (percent) on the joint test set after one session, split the ways OrCo reports it.
struct SessionAccuracy {
  double all = 0;
  double base = 0;      // test samples of base classes
  double novel = 0;     // test samples of classes added in sessions >= 1 (0 after the base session)
  double current = 0;   // test samples of the classes this session introduced
  double harmonic = 0;  // harmonic mean of base and novel
  std::int64_t samples = 0;
};

// Labels and predictions are protocol class indices; classes [current_first, current_end) are
// the ones this session added.
SessionAccuracy score_session(const std::vector<std::int64_t>& labels, const std::vector<std::int64_t>& predictions,
                              int base_classes, int current_first, int current_end);

}  // namespace fscil
