#include "methods/arp/relation_head.h"

namespace fscil {

namespace F = torch::nn::functional;

RelationHeadImpl::RelationHeadImpl(std::int64_t dim, std::int64_t width, double dropout)
    : dim_(dim), dropout_(dropout) {
  pair = register_module("pair", torch::nn::Linear(2 * dim, width));
  pair_norm = register_module("pair_norm", torch::nn::BatchNorm1d(width));
  hidden = register_module("hidden", torch::nn::Linear(width, 64));  // 64 fixed in the release (L113)
  hidden_norm = register_module("hidden_norm", torch::nn::BatchNorm1d(64));
  score = register_module("score", torch::nn::Linear(64, 1));
}

torch::Tensor RelationHeadImpl::forward(const torch::Tensor& embeddings, const torch::Tensor& rows) {
  const auto unit = [](const torch::Tensor& x) { return F::normalize(x, F::NormalizeFuncOptions().dim(1)); };
  const torch::Tensor weight = pair->weight;  // width x 2D: the sample's half, then the row's
  const torch::Tensor from_sample = torch::matmul(unit(embeddings), weight.slice(1, 0, dim_).t());
  const torch::Tensor from_row = torch::addmm(pair->bias, unit(rows), weight.slice(1, dim_).t());
  const std::int64_t samples = embeddings.size(0), classes = rows.size(0);
  torch::Tensor x = (from_sample.unsqueeze(1) + from_row.unsqueeze(0)).reshape({samples * classes, -1});
  const auto drop = [&](const torch::Tensor& t) {
    return F::dropout(t, F::DropoutFuncOptions().p(dropout_).training(is_training()));
  };
  x = drop(pair_norm->forward(x).relu());
  x = drop(hidden_norm->forward(hidden->forward(x)).relu());
  return score->forward(x).view({samples, classes});
}

}  // namespace fscil
