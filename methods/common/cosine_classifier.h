#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// Rows for every class of the protocol; logits = temperature * cos(x, row) over the first
// `seen` rows only, so classes not yet seen take no part in softmax or prediction.
class CosineClassifierImpl : public torch::nn::Module {
 public:
  CosineClassifierImpl(std::int64_t classes, std::int64_t embedding_size, double temperature);
  torch::Tensor forward(const torch::Tensor& embeddings, std::int64_t seen);
  // Overwrites rows [first, first + rows.size(0)) without recording gradients.
  void set_rows(std::int64_t first, const torch::Tensor& rows);
  const torch::Tensor& weight() const { return weight_; }

 private:
  torch::Tensor weight_;
  double temperature_;
};
TORCH_MODULE(CosineClassifier);

}  // namespace fscil
