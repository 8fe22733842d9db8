#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// PAN's one-head self-attention (vinceasvp/FCAC models/stdu/Network.py L311-L357 at 9f784713),
// used both as PQA (`slf_attn`) and for the attention prototypes (`transatt_proto`): on tokens
// T (B x L x D), q = T W_q, k = T W_k, v = T W_v (no biases), A = softmax(q k^T / sqrt(D)) over
// the keys, output = LayerNorm((A v) W_o + b_o + T). Its dropouts (0.5 after W_o, 0.1 on A) are
// left out: the release runs every attention with the model in eval mode (fscil_trainer.py L206,
// L78), where they do nothing.
struct AttentionOutput {
  torch::Tensor tokens;      // B x L x D
  torch::Tensor raw_scores;  // B x L x L, q k^T before the 1/sqrt(D) scaling (the release's attn_logit)
};

class PanAttentionImpl : public torch::nn::Module {
 public:
  explicit PanAttentionImpl(std::int64_t dim);
  AttentionOutput forward(const torch::Tensor& tokens);
  std::int64_t dim() const { return dim_; }

  torch::nn::Linear query{nullptr}, key{nullptr}, value{nullptr}, out{nullptr};
  torch::nn::LayerNorm norm{nullptr};

 private:
  std::int64_t dim_;
};
TORCH_MODULE(PanAttention);

}  // namespace fscil
