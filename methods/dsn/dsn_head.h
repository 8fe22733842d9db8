#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// DSN's head over the encoder's embedding x (models/DSN.py L24-L25, L55-L59 at 5bc87b96): `fc1`,
// a bias-free N x D projection whose output u is L2-normalised, and the base classes' rows, scored
// by cosine against u. Sessions never train it (Inc_train.py L269-L271 steps only the session's
// own head and support branch).
class DsnHeadImpl : public torch::nn::Module {
 public:
  DsnHeadImpl(std::int64_t embedding_size, std::int64_t nodes, std::int64_t base_classes);
  // u = fc1 x / (1e-6 + |fc1 x|) (L55-L56 with l2_norm, L87-L89).
  torch::Tensor project(const torch::Tensor& embeddings) const;
  // cos(u, base row c) for every base class (L59).
  torch::Tensor base_cosines(const torch::Tensor& projected) const;
  const torch::Tensor& projection_weight() const { return fc1->weight; }

  torch::nn::Linear fc1{nullptr};
  torch::nn::Linear base{nullptr};
};
TORCH_MODULE(DsnHead);

// v / (1e-6 + |v|) per row: DSN's l2_norm (L87-L89), whose epsilon differs from F.normalize's.
torch::Tensor dsn_l2_norm(const torch::Tensor& rows);
// cos(a_i, b_j) for every row pair, as F.linear(F.normalize(a), F.normalize(b)) computes it.
torch::Tensor row_cosines(const torch::Tensor& a, const torch::Tensor& b);

}  // namespace fscil
