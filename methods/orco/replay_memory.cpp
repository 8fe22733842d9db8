#include "methods/orco/replay_memory.h"

#include <fmt/format.h>

#include <map>
#include <vector>

#include "core/seeded_shuffle.h"

namespace fscil {

namespace {

std::vector<std::int64_t> first_of_each_class(const std::vector<std::int64_t>& labels, std::int64_t classes,
                                              int per_class) {
  std::vector<std::int64_t> taken(static_cast<std::size_t>(classes), 0), rows;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const std::int64_t label = labels[i];
    if (label < 0 || label >= classes || taken[static_cast<std::size_t>(label)] >= per_class) continue;
    ++taken[static_cast<std::size_t>(label)];
    rows.push_back(static_cast<std::int64_t>(i));
  }
  return rows;
}

std::vector<std::int64_t> across_recordings(const std::vector<std::int64_t>& labels,
                                            const std::vector<std::int64_t>& recordings, std::int64_t classes,
                                            int per_class, std::mt19937_64& generator) {
  std::vector<std::int64_t> rows;
  for (std::int64_t c = 0; c < classes; ++c) {
    std::map<std::int64_t, std::vector<std::int64_t>> by_recording;
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (labels[i] != c) continue;
      by_recording[recordings.empty() ? static_cast<std::int64_t>(i) : recordings[i]].push_back(static_cast<std::int64_t>(i));
    }
    std::vector<std::vector<std::int64_t>> pools;
    for (auto& [recording, members] : by_recording) {
      shuffle_with(members, generator);
      pools.push_back(std::move(members));
    }
    shuffle_with(pools, generator);
    std::size_t round = 0;
    int chosen = 0;
    while (chosen < per_class) {
      bool any = false;
      for (const auto& pool : pools) {
        if (round >= pool.size() || chosen == per_class) continue;
        rows.push_back(pool[round]);
        ++chosen;
        any = true;
      }
      if (!any) break;
      ++round;
    }
  }
  return rows;
}

}  // namespace

void ReplayMemory::keep_base_exemplars(const SessionData& base, std::int64_t base_classes, int per_class,
                                       ExemplarSource source, std::mt19937_64& generator) {
  const torch::Tensor label_tensor = base.labels.contiguous();
  const std::vector<std::int64_t> labels(label_tensor.data_ptr<std::int64_t>(),
                                         label_tensor.data_ptr<std::int64_t>() + label_tensor.numel());
  if (!base.recordings.empty() && base.recordings.size() != labels.size()) {
    throw MethodError(fmt::format("{} recordings for {} base samples", base.recordings.size(), labels.size()));
  }
  const std::vector<std::int64_t> rows =
      source == ExemplarSource::first ? first_of_each_class(labels, base_classes, per_class)
                                      : across_recordings(labels, base.recordings, base_classes, per_class, generator);
  const torch::Tensor index = torch::tensor(rows, torch::kLong);
  keep_all(base.features.gather(index), base.labels.index_select(0, index));
}

void ReplayMemory::keep_all(const torch::Tensor& features, const torch::Tensor& labels) {
  features_ = features_.defined() ? torch::cat({features_, features}) : features.clone();
  labels_ = labels_.defined() ? torch::cat({labels_, labels}) : labels.clone();
}

}  // namespace fscil
