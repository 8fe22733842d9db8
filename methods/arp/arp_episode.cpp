#include "methods/arp/arp_episode.h"

#include <algorithm>
#include <numeric>

#include "core/random_draws.h"
#include "core/seeded_shuffle.h"
#include "methods/common/class_members.h"

namespace fscil {

ArpEpisodeSampler::ArpEpisodeSampler(const SessionData& base, std::int64_t base_classes, int way, int shot, int tasks)
    : base_(base),
      base_classes_(base_classes),
      episode_classes_(std::min<std::int64_t>(way + tasks, base_classes)),
      way_(static_cast<int>(std::min<std::int64_t>(way, episode_classes_))),
      shot_(shot),
      tasks_(tasks),
      members_(base_class_members(base.labels, base_classes)) {}

ArpEpisode ArpEpisodeSampler::draw(std::mt19937_64& generator) const {
  std::vector<std::int64_t> classes(base_classes_);
  std::iota(classes.begin(), classes.end(), 0);
  shuffle_with(classes, generator);
  classes.resize(episode_classes_);
  std::vector<std::int64_t> rows;
  rows.reserve(static_cast<std::size_t>(episode_classes_ * shot_));
  for (std::int64_t label : classes) {
    std::vector<std::int64_t> samples = members_[label];
    shuffle_with(samples, generator);
    for (int s = 0; s < shot_; ++s) {
      // With replacement only where a class has fewer samples than shots (a small protocol; ours).
      rows.push_back(s < static_cast<int>(samples.size()) ? samples[s]
                                                          : samples[uniform_index(generator, samples.size())]);
    }
  }
  ArpEpisode episode{base_.features.gather(torch::tensor(rows)), torch::tensor(classes), {}};
  for (int t = 0; t < tasks_; ++t) {  // torch.randperm(way + batch_task)[:way] per task (L221)
    std::vector<std::int64_t> slots(episode_classes_);
    std::iota(slots.begin(), slots.end(), 0);
    shuffle_with(slots, generator);
    slots.resize(way_);
    episode.task_slots.push_back(torch::tensor(slots));
  }
  return episode;
}

torch::Tensor support_means(const torch::Tensor& support_embeddings, std::int64_t shot) {
  return support_embeddings.view({-1, shot, support_embeddings.size(1)}).mean(1);
}

}  // namespace fscil
