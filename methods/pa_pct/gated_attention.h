#pragma once
#include <torch/torch.h>

#include <cstdint>

#include "methods/pan/pan_attention.h"

namespace fscil {

// PA-PCT's two-branch PQA after the base session (cgq2971-afk/FCIAC CANetwork.py L212-L222 at
// 6ccc2082): PAN's attention (`slf_attn`, frozen once PAN's stages end) and an incremental copy of
// it (`inc_attn`, copied when PCTS begins, T L231-L234) each map the tokens, and a per-token gate
// g = sigmoid(MLP([c1; c2])), 2D -> D / 2 -> 1 with a ReLU (L135-L140), mixes them:
// (1 - g) c1 + g c2. The release scores session 0 through it too (its session index is left at 1
// by PCTS's last test, T L544). Both branches carry the release's dropouts (0.1 on the weights,
// 0.5 on the output: L143-L150, L811, L830), which act in train mode: PCTS trains the whole model
// so (PCA.py L60), a session only inc_attn and the gate (N L416-L419).
class GatedAttentionImpl : public torch::nn::Module {
 public:
  explicit GatedAttentionImpl(std::int64_t dim);
  // tokens B x L x D -> B x L x D.
  torch::Tensor forward(const torch::Tensor& tokens);
  // The gate's value per token, B x L x 1, for the same tokens.
  torch::Tensor gate_of(const torch::Tensor& settled_tokens, const torch::Tensor& incremental_tokens);

  PanAttention settled{nullptr};      // slf_attn
  PanAttention incremental{nullptr};  // inc_attn
  torch::nn::Sequential gate{nullptr};
};
TORCH_MODULE(GatedAttention);

}  // namespace fscil
