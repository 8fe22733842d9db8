#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// PAN's one-head self-attention (vinceasvp/FCAC models/stdu/Network.py L311-L357 at 9f784713),
// used both as PQA (`slf_attn`) and for the attention prototypes (`transatt_proto`): on tokens
// T (B x L x D), q = T W_q, k = T W_k, v = T W_v (no biases), A = softmax(q k^T / sqrt(D)) over
// the keys, output = LayerNorm((A v) W_o + b_o + T). Its dropouts (0.1 on A, 0.5 after W_o) act
// only where a release trains an attention in train mode: PAN's never does (fscil_trainer.py L206,
// L78), so PAN builds it without them; PA-PCT's PCTS and sessions do (AttentionDropouts).
struct AttentionOutput {
  torch::Tensor tokens;      // B x L x D
  torch::Tensor raw_scores;  // B x L x L, q k^T before the 1/sqrt(D) scaling (the release's attn_logit)
};

// Dropout probabilities, applied in train mode only; none by default.
struct AttentionDropouts {
  double weights = 0;  // on A (ScaledDotProductAttention's attn_dropout)
  double output = 0;   // on (A v) W_o + b_o, before the residual (MultiHeadAttention's dropout)
};

class PanAttentionImpl : public torch::nn::Module {
 public:
  explicit PanAttentionImpl(std::int64_t dim, AttentionDropouts dropouts = {});
  AttentionOutput forward(const torch::Tensor& tokens);
  std::int64_t dim() const { return dim_; }

  torch::nn::Linear query{nullptr}, key{nullptr}, value{nullptr}, out{nullptr};
  torch::nn::LayerNorm norm{nullptr};

 private:
  std::int64_t dim_;
  AttentionDropouts dropouts_;
};
TORCH_MODULE(PanAttention);

}  // namespace fscil
