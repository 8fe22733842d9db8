#include "methods/pan/pan_attention.h"

#include <cmath>

namespace fscil {

PanAttentionImpl::PanAttentionImpl(std::int64_t dim, AttentionDropouts dropouts) : dim_(dim), dropouts_(dropouts) {
  const auto projection = [dim] { return torch::nn::Linear(torch::nn::LinearOptions(dim, dim).bias(false)); };
  query = register_module("query", projection());
  key = register_module("key", projection());
  value = register_module("value", projection());
  out = register_module("out", torch::nn::Linear(dim, dim));
  norm = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({dim})));
  torch::NoGradGuard no_grad;
  // The release's initialisation (Network.py L323-L331): N(0, sqrt(2 / (D + D))) for the projections,
  // Xavier-normal for W_o (its bias keeps Linear's default).
  const double spread = std::sqrt(2.0 / static_cast<double>(dim + dim));
  for (auto* linear : {&query, &key, &value}) torch::nn::init::normal_((*linear)->weight, 0.0, spread);
  torch::nn::init::xavier_normal_(out->weight);
}

AttentionOutput PanAttentionImpl::forward(const torch::Tensor& tokens) {
  const torch::Tensor q = query->forward(tokens), k = key->forward(tokens), v = value->forward(tokens);
  const torch::Tensor raw_scores = torch::bmm(q, k.transpose(1, 2));
  const auto dropped = [this](const torch::Tensor& x, double p) {
    return p > 0 && is_training() ? torch::dropout(x, p, true) : x;
  };
  const torch::Tensor weights =
      dropped(torch::softmax(raw_scores / std::sqrt(static_cast<double>(dim_)), -1), dropouts_.weights);
  return {norm->forward(dropped(out->forward(torch::bmm(weights, v)), dropouts_.output) + tokens), raw_scores};
}

}  // namespace fscil
