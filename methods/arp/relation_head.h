#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// ARP's relation head (`self.embedding` and `forward_metric`, chester-w-xie/APR
// FSCIL_model_define_V1.py L108-L119, L167-L186 at 78426ecf): every (sample, class) pair of the
// L2-normalised embedding and the L2-normalised class row, concatenated (sample first), passes
// through 2D -> width (`--embedding`, 64) -> 64 -> 1 with BatchNorm, ReLU and dropout 0.5 after each hidden layer;
// the output, with no sigmoid, is the pair's logit. The release's layers are 1x1 convolutions on
// (pairs x 2D x 1 x 1), which are these linear layers (same default initialisation). The first
// layer is applied to the sample and row halves apart and summed, which is the same product as on
// their concatenation without building B x C x 2D pairs.
class RelationHeadImpl : public torch::nn::Module {
 public:
  RelationHeadImpl(std::int64_t dim, std::int64_t width = 64, double dropout = 0.5);
  // B x D embeddings, C x D rows -> B x C logits.
  torch::Tensor forward(const torch::Tensor& embeddings, const torch::Tensor& rows);

  torch::nn::Linear pair{nullptr}, hidden{nullptr}, score{nullptr};
  torch::nn::BatchNorm1d pair_norm{nullptr}, hidden_norm{nullptr};

 private:
  std::int64_t dim_;
  double dropout_;
};
TORCH_MODULE(RelationHead);

}  // namespace fscil
