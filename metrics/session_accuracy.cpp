#include "metrics/session_accuracy.h"

#include <stdexcept>

namespace fscil {

namespace {
struct Tally {
  std::int64_t correct = 0, total = 0;
  void add(bool hit) { correct += hit ? 1 : 0, ++total; }
  double percent() const { return total == 0 ? 0.0 : 100.0 * static_cast<double>(correct) / total; }
};
}  // namespace

SessionAccuracy score_session(const std::vector<std::int64_t>& labels, const std::vector<std::int64_t>& predictions,
                              int base_classes, int current_first, int current_end) {
  if (labels.size() != predictions.size()) throw std::invalid_argument("labels and predictions differ in length");
  Tally all, base, novel, current;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const bool hit = labels[i] == predictions[i];
    all.add(hit);
    (labels[i] < base_classes ? base : novel).add(hit);
    if (labels[i] >= current_first && labels[i] < current_end) current.add(hit);
  }
  SessionAccuracy result;
  result.all = all.percent();
  result.base = base.percent();
  result.novel = novel.percent();
  result.current = current.percent();
  result.samples = all.total;
  result.harmonic = novel.total == 0 ? 0.0 : harmonic_mean(result.base, result.novel);
  return result;
}

CrossGroupErrors cross_group_errors(const std::vector<std::int64_t>& labels,
                                    const std::vector<std::int64_t>& predictions, int base_classes) {
  if (labels.size() != predictions.size()) throw std::invalid_argument("labels and predictions differ in length");
  Tally base_as_novel, novel_as_base;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const bool label_is_base = labels[i] < base_classes, predicted_base = predictions[i] < base_classes;
    (label_is_base ? base_as_novel : novel_as_base).add(label_is_base != predicted_base);
  }
  return {base_as_novel.percent(), novel_as_base.percent()};
}

}  // namespace fscil
