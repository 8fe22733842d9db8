#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>

#include "methods/method.h"
#include "methods/orco/orco_settings.h"
#include "methods/sample_rows.h"

namespace fscil {

// The real old samples OrCo keeps: `per_class` samples of every base class and every shot of
// every incremental session.
class ReplayMemory {
 public:
  // `first`: the first `per_class` of each class in the order the session gives them (the
  // reference's choice; on segmented recordings they are consecutive segments of one recording).
  // `recordings`: one random segment from each of `per_class` distinct recordings drawn at random,
  // going round the recordings again only when a class has fewer.
  void keep_base_exemplars(const SessionData& base, std::int64_t base_classes, int per_class, ExemplarSource source,
                           std::mt19937_64& generator);
  void keep_all(const torch::Tensor& features, const torch::Tensor& labels);

  const torch::Tensor& features() const { return features_; }
  const torch::Tensor& labels() const { return labels_; }
  std::int64_t samples() const { return labels_.defined() ? labels_.size(0) : 0; }
  // Bytes of the stored inputs, the memory a deployment of the method has to keep.
  std::int64_t bytes() const { return features_.defined() ? features_.numel() * features_.element_size() : 0; }

 private:
  torch::Tensor features_, labels_;
};

}  // namespace fscil
