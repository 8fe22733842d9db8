#include "methods/dsn/dsn_head.h"

namespace fscil {

namespace F = torch::nn::functional;

DsnHeadImpl::DsnHeadImpl(std::int64_t embedding_size, std::int64_t nodes, std::int64_t base_classes) {
  // PyTorch's default Linear initialisation, as the release's (no init of its own for either).
  fc1 = register_module("fc1", torch::nn::Linear(torch::nn::LinearOptions(embedding_size, nodes).bias(false)));
  base = register_module("base", torch::nn::Linear(torch::nn::LinearOptions(nodes, base_classes).bias(false)));
}

torch::Tensor DsnHeadImpl::project(const torch::Tensor& embeddings) const {
  return dsn_l2_norm(F::linear(embeddings, fc1->weight));
}

torch::Tensor DsnHeadImpl::base_cosines(const torch::Tensor& projected) const {
  return row_cosines(projected, base->weight);
}

torch::Tensor dsn_l2_norm(const torch::Tensor& rows) { return rows / (rows.norm(2, -1, true) + 1e-6); }

torch::Tensor row_cosines(const torch::Tensor& a, const torch::Tensor& b) {
  const auto unit = F::NormalizeFuncOptions().dim(-1);
  return F::normalize(a, unit).matmul(F::normalize(b, unit).t());
}

}  // namespace fscil
