#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>

#include "methods/pan/pan_attention.h"

namespace fscil {

// PAN's prototype-query attention (PQA; vinceasvp/FCAC models/stdu/Network.py L71-L81 at 9f784713):
// each query x_n passes through the attention together with its own set of prototypes, the tokens
// [p_1 .. p_C, x_n], and its logits are temperature x cos(x'_n, p'_c) of the outputs.
// `prototypes` is C x D (one set for every query: tests) or N x C x D (a set per query: episodes);
// `queries` N x D. Queries go through `chunk` at a time, so memory stays at chunk x (C + 1) x D.
torch::Tensor pqa_logits(PanAttention& attention, const torch::Tensor& prototypes, const torch::Tensor& queries,
                         double temperature, std::int64_t chunk = 256);
// The same through any attention over tokens B x L x D (PA-PCT's gated two-branch one); with
// `adapted_rows`, also the prototypes' outputs averaged over the queries (C x D, shared prototypes
// only: the release's `avg_by_class`).
torch::Tensor pqa_logits(const std::function<torch::Tensor(const torch::Tensor&)>& attend, const torch::Tensor& prototypes,
                         const torch::Tensor& queries, double temperature, std::int64_t chunk = 256,
                         torch::Tensor* adapted_rows = nullptr);

}  // namespace fscil
