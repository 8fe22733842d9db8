#include "methods/pan/attention_prototypes.h"

namespace fscil {

torch::Tensor attention_prototypes(PanAttention& attention, const torch::Tensor& supports, const torch::Tensor& queries,
                                   std::int64_t shot) {
  const std::int64_t n = queries.size(0), s = supports.size(0), dim = supports.size(1), groups = s / shot;
  const torch::Tensor tokens =
      torch::cat({supports.unsqueeze(0).expand({n, s, dim}), queries.unsqueeze(1)}, 1);  // N x (S + 1) x D
  const AttentionOutput out = attention->forward(tokens);
  // l_j = (W_q s_j).(W_k x_n): support j's row, the query's column.
  const torch::Tensor scores = out.raw_scores.slice(1, 0, s).select(2, s);  // N x S
  const torch::Tensor weights = torch::softmax(scores.view({n, shot, groups}), 1);  // over the shots of a group
  const torch::Tensor outputs = out.tokens.slice(1, 0, s).view({n, shot, groups, dim});
  return (weights.unsqueeze(3) * outputs).sum(1);  // N x W x D
}

}  // namespace fscil
