#include "methods/orco/replay_memory.h"

#include <vector>

namespace fscil {

void ReplayMemory::keep_base_exemplars(const SampleRows& features, const torch::Tensor& labels,
                                       std::int64_t base_classes, int per_class) {
  std::vector<std::int64_t> taken(static_cast<std::size_t>(base_classes), 0), rows;
  const auto label_values = labels.accessor<std::int64_t, 1>();
  for (std::int64_t i = 0; i < labels.size(0); ++i) {
    const std::int64_t label = label_values[i];
    if (label < 0 || label >= base_classes || taken[static_cast<std::size_t>(label)] >= per_class) continue;
    ++taken[static_cast<std::size_t>(label)];
    rows.push_back(i);
  }
  const torch::Tensor index = torch::tensor(rows, torch::kLong);
  keep_all(features.gather(index), labels.index_select(0, index));
}

void ReplayMemory::keep_all(const torch::Tensor& features, const torch::Tensor& labels) {
  features_ = features_.defined() ? torch::cat({features_, features}) : features.clone();
  labels_ = labels_.defined() ? torch::cat({labels_, labels}) : labels.clone();
}

}  // namespace fscil
