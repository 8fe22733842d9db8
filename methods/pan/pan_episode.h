#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>
#include <vector>

#include "methods/method.h"

namespace fscil {

// One pseudo-incremental episode of PAN (vinceasvp/FCAC dataloader/sampler.py L70-L93 at
// 090e91df): `way` temporary base classes, then `way` temporary novel classes, each with `shot`
// supports and `query` queries drawn without replacement (with replacement past the samples a
// class has: ours, for small protocols). Each part is laid out sample-major
// (row = sample x way + class slot; samples [0, shot) are supports), as the release's sampler
// lays it out, since its attention prototypes group supports by that layout.
struct PanEpisode {
  torch::Tensor base_features, novel_features;  // (shot + query) x way rows each
  std::int64_t way = 0, shot = 0, query = 0;
};

class PanEpisodeSampler {
 public:
  // Temporary base classes are [0, temporary_base), temporary novel [temporary_base, base_classes),
  // as the release takes 0..34 and 35..59 of LS-100's base classes. Ways shrink to fit a small
  // protocol (ours: tests).
  PanEpisodeSampler(const SessionData& base, std::int64_t temporary_base, std::int64_t base_classes, int way, int shot,
                    int query);
  PanEpisode draw(std::mt19937_64& generator) const;

 private:
  torch::Tensor part(std::int64_t first_class, std::int64_t classes, std::int64_t way,
                     std::mt19937_64& generator) const;

  const SessionData& base_;
  std::int64_t temporary_base_, base_classes_, base_way_, novel_way_;
  int shot_, query_;
  std::vector<std::vector<std::int64_t>> members_;
};

}  // namespace fscil
