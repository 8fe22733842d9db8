#include "methods/common/cosine_classifier.h"

namespace fscil {

namespace F = torch::nn::functional;

CosineClassifierImpl::CosineClassifierImpl(std::int64_t classes, std::int64_t embedding_size, double temperature)
    : weight_(register_parameter("weight", 0.01 * torch::randn({classes, embedding_size}))),
      temperature_(temperature) {}

torch::Tensor CosineClassifierImpl::forward(const torch::Tensor& embeddings, std::int64_t seen) {
  const auto rows = F::normalize(weight_.narrow(0, 0, seen), F::NormalizeFuncOptions().dim(1));
  return temperature_ * torch::mm(F::normalize(embeddings, F::NormalizeFuncOptions().dim(1)), rows.t());
}

void CosineClassifierImpl::set_rows(std::int64_t first, const torch::Tensor& rows) {
  torch::NoGradGuard no_grad;
  weight_.narrow(0, first, rows.size(0)).copy_(rows);
}

}  // namespace fscil
