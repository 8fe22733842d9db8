#include "methods/pa_pct/pcts_losses.h"

namespace fscil {

namespace {

// L = diag(W 1) - W of the cosine-similarity graph W_ij = exp(-(1 - cos(p_i, p_j)) / sigma).
torch::Tensor graph_laplacian(const torch::Tensor& prototypes, double sigma) {
  namespace F = torch::nn::functional;
  const torch::Tensor unit = F::normalize(prototypes, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor weights = torch::exp(-(1 - unit.matmul(unit.t())) / sigma);
  return torch::diag(weights.sum(1)) - weights;
}

}  // namespace

torch::Tensor forgetting_separation_loss(const torch::Tensor& forgotten, const torch::Tensor& retained, double margin) {
  return torch::relu(margin - torch::cdist(forgotten, retained)).mean();
}

torch::Tensor topology_distillation_loss(const torch::Tensor& before, const torch::Tensor& now, double sigma) {
  const double rows = static_cast<double>(now.size(0));
  return (graph_laplacian(before, sigma) - graph_laplacian(now, sigma)).pow(2).sum() / (rows * rows);
}

}  // namespace fscil
