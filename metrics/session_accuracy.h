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

// The harmonic mean of the base and the novel accuracy (0 when both are 0), as every session reports it.
inline double harmonic_mean(double base, double novel) {
  return base + novel == 0 ? 0.0 : 2 * base * novel / (base + novel);
}

// Labels and predictions are protocol class indices; classes [current_first, current_end) are
// the ones this session added.
SessionAccuracy score_session(const std::vector<std::int64_t>& labels, const std::vector<std::int64_t>& predictions,
                              int base_classes, int current_first, int current_end);

// Where the errors between the two groups go: the percentage of base-class samples predicted as a
// novel class, and of novel-class samples predicted as a base class (0 for an empty group). High
// base_as_novel with base accuracy falling is a bias toward new rows; low, confusion among the old.
struct CrossGroupErrors {
  double base_as_novel = 0;
  double novel_as_base = 0;
};
CrossGroupErrors cross_group_errors(const std::vector<std::int64_t>& labels,
                                    const std::vector<std::int64_t>& predictions, int base_classes);

}  // namespace fscil
