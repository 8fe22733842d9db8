#include "methods/comp_fscil/compositional_heads.h"

namespace fscil {

namespace F = torch::nn::functional;

namespace {

// N x D x ... -> N x D x n, each column (position) minus its mean over the D channels.
torch::Tensor centred_columns(const torch::Tensor& maps) {
  const torch::Tensor columns = maps.flatten(2);
  return columns - columns.mean(1, true);
}

// ||X^T X||_F per set: X N x D x n.
torch::Tensor gram_norms(const torch::Tensor& columns) {
  return columns.transpose(1, 2).bmm(columns).flatten(1).norm(2, 1);
}

// ||A_i^T P_k||_F^2 for every sample i and prototype k: A N x D x n, P K x D x m.
torch::Tensor cross_gram_energy(const torch::Tensor& a, const torch::Tensor& p) {
  const std::int64_t n = a.size(0), positions = a.size(2), k = p.size(0), m = p.size(2);
  const torch::Tensor rows = a.transpose(1, 2).reshape({n * positions, a.size(1)});
  const torch::Tensor cols = p.permute({1, 0, 2}).reshape({p.size(1), k * m});
  return rows.matmul(cols).view({n, positions, k, m}).pow(2).sum({1, 3});
}

// ||x_i - y_j||^2 for every pair (the release's cdist^2), expanded into one matrix product rather
// than a pairs x D difference tensor (for primitive reuse, (B m)^2 x D).
torch::Tensor squared_distances(const torch::Tensor& x, const torch::Tensor& y) {
  return x.pow(2).sum(1, true) + y.pow(2).sum(1).unsqueeze(0) - 2 * x.matmul(y.t());
}

}  // namespace

torch::Tensor signed_power(const torch::Tensor& x, double p) { return torch::relu(x).pow(p) - torch::relu(-x); }

torch::Tensor cka_similarity(const torch::Tensor& maps, const torch::Tensor& prototypes) {
  const torch::Tensor a = centred_columns(maps), p = centred_columns(prototypes);
  const torch::Tensor denominator = gram_norms(a).unsqueeze(1) * gram_norms(p).unsqueeze(0);
  return cross_gram_energy(a, p) / denominator.clamp_min(1e-12);
}

torch::Tensor vector_distance_logits(const torch::Tensor& pooled, const torch::Tensor& rows, double temperature) {
  const torch::Tensor x = pooled - pooled.mean(1, true), w = rows - rows.mean(1, true);
  return -temperature * squared_distances(x, w);
}

torch::Tensor vector_cosine_logits(const torch::Tensor& pooled, const torch::Tensor& rows, double temperature) {
  const auto unit = F::NormalizeFuncOptions().dim(1);
  const torch::Tensor x = F::normalize(pooled - pooled.mean(1, true), unit);
  const torch::Tensor w = F::normalize(rows - rows.mean(1, true), unit);
  return temperature * x.matmul(w.t());
}

torch::Tensor reuse_similarity(const torch::Tensor& maps, const torch::Tensor& prototypes, double tau) {
  const torch::Tensor a = centred_columns(maps), p = centred_columns(prototypes);
  const std::int64_t classes = p.size(0), dim = p.size(1), m = p.size(2);
  const torch::Tensor primitives = p.transpose(1, 2).reshape({classes * m, dim});  // class-major
  const torch::Tensor owner = torch::arange(classes).repeat_interleave(m);
  const torch::Tensor own_class = (owner.unsqueeze(1) == owner.unsqueeze(0)).to(primitives.dtype());
  const torch::Tensor scores = -squared_distances(primitives, primitives) - 9999.0 * own_class;
  const torch::Tensor weights = torch::softmax(tau * scores, 1).detach();
  const torch::Tensor rebuilt = weights.matmul(primitives).view({classes, m, dim}).transpose(1, 2);
  const torch::Tensor denominator = gram_norms(a).unsqueeze(1) * gram_norms(rebuilt).unsqueeze(0) + 1e-6;
  return cross_gram_energy(a, rebuilt) / denominator;
}

}  // namespace fscil
