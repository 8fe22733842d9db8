#pragma once
#include <torch/torch.h>

#include <cstdint>

#include "methods/sample_rows.h"

namespace fscil {

// The real old samples OrCo keeps: the first `per_class` samples of every base class (in the
// order the session gives them) and every shot of every incremental session.
class ReplayMemory {
 public:
  void keep_base_exemplars(const SampleRows& features, const torch::Tensor& labels, std::int64_t base_classes,
                           int per_class);
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
