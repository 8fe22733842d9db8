#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// The stochastic cosine classifier of PITS-SC and S3C. Each class row has a mean mu
// (0.01 * randn) and a spread sigma (0). A stochastic forward draws
// W = mu + softplus(sigma - 4) * eps with fresh eps ~ N(0, 1); a deterministic one uses W = mu.
// Logits are temperature * cos(x, W) over the first `seen` rows only, so rows of classes not
// yet seen take no part in softmax or prediction.
class StochasticClassifierImpl : public torch::nn::Module {
 public:
  StochasticClassifierImpl(std::int64_t classes, std::int64_t embedding_size, double temperature = 16.0);
  torch::Tensor forward(const torch::Tensor& embeddings, std::int64_t seen, bool stochastic);
  // Overwrites mu rows [first, first + rows.size(0)) without recording gradients.
  void set_mu_rows(std::int64_t first, const torch::Tensor& rows);
  // The standard deviation of the noise added to each weight in a stochastic forward.
  torch::Tensor noise_scale() const;

  torch::Tensor mu, sigma;

 private:
  double temperature_;
};
TORCH_MODULE(StochasticClassifier);

}  // namespace fscil
