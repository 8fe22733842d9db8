#include "methods/pa_pct/gated_attention.h"

namespace fscil {

GatedAttentionImpl::GatedAttentionImpl(std::int64_t dim) {
  const AttentionDropouts release{0.1, 0.5};
  settled = register_module("settled", PanAttention(dim, release));
  incremental = register_module("incremental", PanAttention(dim, release));
  gate = register_module("gate", torch::nn::Sequential(torch::nn::Linear(2 * dim, dim / 2), torch::nn::ReLU(),
                                                       torch::nn::Linear(dim / 2, 1), torch::nn::Sigmoid()));
}

torch::Tensor GatedAttentionImpl::gate_of(const torch::Tensor& settled_tokens, const torch::Tensor& incremental_tokens) {
  return gate->forward(torch::cat({settled_tokens, incremental_tokens}, -1));
}

torch::Tensor GatedAttentionImpl::forward(const torch::Tensor& tokens) {
  const torch::Tensor first = settled->forward(tokens).tokens, second = incremental->forward(tokens).tokens;
  const torch::Tensor mix = gate_of(first, second);
  return (1 - mix) * first + mix * second;
}

}  // namespace fscil
