#include "methods/pan/pan_episode.h"

#include <algorithm>
#include <numeric>

#include "core/random_draws.h"
#include "core/seeded_shuffle.h"
#include "methods/common/class_members.h"

namespace fscil {

PanEpisodeSampler::PanEpisodeSampler(const SessionData& base, std::int64_t temporary_base, std::int64_t base_classes,
                                     int way, int shot, int query)
    : base_(base),
      temporary_base_(temporary_base),
      base_classes_(base_classes),
      base_way_(std::min<std::int64_t>(way, temporary_base)),
      novel_way_(std::min<std::int64_t>(way, base_classes - temporary_base)),
      shot_(shot),
      query_(query),
      members_(base_class_members(base.labels, base_classes)) {
  // The episode's two parts must pair up slot by slot for the release's grouping.
  if (base_way_ != novel_way_) base_way_ = novel_way_ = std::min(base_way_, novel_way_);
}

torch::Tensor PanEpisodeSampler::part(std::int64_t first_class, std::int64_t classes, std::int64_t way,
                                      std::mt19937_64& generator) const {
  std::vector<std::int64_t> pool(classes);
  std::iota(pool.begin(), pool.end(), first_class);
  shuffle_with(pool, generator);
  const std::int64_t per_class = shot_ + query_;
  std::vector<std::int64_t> rows(static_cast<std::size_t>(per_class * way));
  for (std::int64_t slot = 0; slot < way; ++slot) {
    std::vector<std::int64_t> samples = members_[pool[slot]];
    shuffle_with(samples, generator);
    for (std::int64_t s = 0; s < per_class; ++s) {
      // With replacement only where a class has too few samples (a small protocol; ours).
      rows[s * way + slot] = s < static_cast<std::int64_t>(samples.size())
                                 ? samples[s]
                                 : samples[uniform_index(generator, samples.size())];
    }
  }
  return base_.features.gather(torch::tensor(rows));
}

PanEpisode PanEpisodeSampler::draw(std::mt19937_64& generator) const {
  PanEpisode episode;
  episode.way = base_way_;
  episode.shot = shot_;
  episode.query = query_;
  episode.base_features = part(0, temporary_base_, base_way_, generator);
  episode.novel_features = part(temporary_base_, base_classes_ - temporary_base_, novel_way_, generator);
  return episode;
}

}  // namespace fscil
