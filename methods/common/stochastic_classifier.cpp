#include "methods/common/stochastic_classifier.h"

namespace fscil {

namespace F = torch::nn::functional;

StochasticClassifierImpl::StochasticClassifierImpl(std::int64_t classes, std::int64_t embedding_size,
                                                   double temperature)
    : mu(register_parameter("mu", 0.01 * torch::randn({classes, embedding_size}))),
      sigma(register_parameter("sigma", torch::zeros({classes, embedding_size}))),
      temperature_(temperature) {}

torch::Tensor StochasticClassifierImpl::noise_scale() const { return F::softplus(sigma - 4); }

torch::Tensor StochasticClassifierImpl::forward(const torch::Tensor& embeddings, std::int64_t seen, bool stochastic) {
  torch::Tensor weight = mu.narrow(0, 0, seen);
  if (stochastic) weight = weight + noise_scale().narrow(0, 0, seen) * torch::randn_like(weight);
  const auto unit = F::NormalizeFuncOptions().dim(1);
  return temperature_ * torch::mm(F::normalize(embeddings, unit), F::normalize(weight, unit).t());
}

void StochasticClassifierImpl::set_mu_rows(std::int64_t first, const torch::Tensor& rows) {
  torch::NoGradGuard no_grad;
  mu.narrow(0, first, rows.size(0)).copy_(rows);
}

}  // namespace fscil
