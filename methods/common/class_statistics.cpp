#include "methods/common/class_statistics.h"

#include "methods/common/embedding.h"

namespace fscil {

torch::Tensor sample_covariance(const torch::Tensor& rows) {
  const std::int64_t n = rows.size(0);
  if (n < 2) return torch::zeros({rows.size(1), rows.size(1)}, rows.options());
  const torch::Tensor centred = rows - rows.mean(0, true);
  return centred.t().matmul(centred) / static_cast<double>(n - 1);
}

torch::Tensor gaussian_factor(const torch::Tensor& covariance) {
  const auto [values, vectors] = torch::linalg::eigh(covariance.to(torch::kDouble), "L");
  return vectors * values.clamp_min(0).sqrt().unsqueeze(0);
}

std::pair<torch::Tensor, torch::Tensor> class_statistics(const torch::Tensor& embeddings, const torch::Tensor& labels,
                                                          const std::vector<std::int64_t>& classes) {
  std::vector<torch::Tensor> covariances;
  for (std::int64_t c : classes) {
    covariances.push_back(sample_covariance(embeddings.index_select(0, torch::nonzero(labels == c).view(-1))));
  }
  return {class_means(embeddings, labels, classes), torch::stack(covariances)};
}

}  // namespace fscil
