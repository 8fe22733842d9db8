#include "methods/arp/refinement_attention.h"

#include <cmath>

namespace fscil {

namespace F = torch::nn::functional;

RefinementAttentionImpl::RefinementAttentionImpl(std::int64_t dim, double dropout) : dim_(dim), dropout_(dropout) {
  const auto projection = [dim] { return torch::nn::Linear(torch::nn::LinearOptions(dim, dim).bias(false)); };
  query = register_module("query", projection());
  key = register_module("key", projection());
  value = register_module("value", projection());
  out = register_module("out", projection());
  torch::NoGradGuard no_grad;
  // L58-L64: N(0, sqrt(2 / (d_model + d_k))) for the projections, Xavier-normal for W_o.
  const double spread = std::sqrt(2.0 / static_cast<double>(dim + dim));
  for (auto* linear : {&query, &key, &value}) torch::nn::init::normal_((*linear)->weight, 0.0, spread);
  torch::nn::init::xavier_normal_(out->weight);
}

torch::Tensor RefinementAttentionImpl::forward(const torch::Tensor& rows, const torch::Tensor& keys) {
  const torch::Tensor sequence = torch::cat({rows, keys});  // the queries join the keys and values (L75-L78)
  const torch::Tensor scores =
      torch::matmul(query->forward(rows), key->forward(sequence).t()) / std::sqrt(static_cast<double>(dim_));
  const torch::Tensor weights =
      F::dropout(torch::softmax(scores, -1), F::DropoutFuncOptions().p(dropout_).training(is_training()));
  const torch::Tensor attended = out->forward(torch::matmul(weights, value->forward(sequence)));
  return F::dropout(attended, F::DropoutFuncOptions().p(dropout_).training(is_training())) + rows;
}

torch::Tensor refine_task_rows(RefinementAttention& attention, const torch::Tensor& rows,
                               const torch::Tensor& task_classes, const torch::Tensor& means) {
  return attention->forward(rows.index_copy(0, task_classes, means), rows.index_fill(0, task_classes, 0.0));
}

torch::Tensor refine_seen_rows(RefinementAttention& attention, const torch::Tensor& rows, std::int64_t base) {
  const bool was_training = attention->is_training();
  attention->eval();
  torch::Tensor keys = rows.clone();
  keys.slice(0, base).zero_();
  const torch::Tensor refined = attention->forward(rows, keys);
  attention->train(was_training);
  return refined;
}

}  // namespace fscil
