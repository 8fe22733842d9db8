#include "methods/dsn/class_gaussians.h"

#include <algorithm>

#include "methods/common/class_statistics.h"

namespace fscil {

ClassGaussiansImpl::ClassGaussiansImpl(std::int64_t classes, std::int64_t embedding_size)
    : factors_(static_cast<std::size_t>(classes)) {
  means_ = register_buffer("means", torch::zeros({classes, embedding_size}));
  covariances_ = register_buffer("covariances", torch::zeros({classes, embedding_size, embedding_size}));
  extra_draws_ = register_buffer("extra_draws", torch::zeros({classes}, torch::kLong));
}

void ClassGaussiansImpl::insert(std::int64_t first, const torch::Tensor& means, const torch::Tensor& covariances) {
  const std::int64_t n = means.size(0);
  means_.slice(0, first, first + n).copy_(means);
  covariances_.slice(0, first, first + n).copy_(covariances);
  extra_draws_.slice(0, first, first + n).zero_();
  for (std::int64_t c = first; c < first + n; ++c) factors_[c] = torch::Tensor();
}

void ClassGaussiansImpl::blend(std::int64_t first, const torch::Tensor& means, const torch::Tensor& covariances) {
  const std::int64_t n = means.size(0);
  means_.slice(0, first, first + n).mul_(0.8).add_(means, 0.2);
  covariances_.slice(0, first, first + n).mul_(0.8).add_(covariances, 0.2);
  for (std::int64_t c = first; c < first + n; ++c) factors_[c] = torch::Tensor();
}

GaussianDraws ClassGaussiansImpl::draw(std::int64_t seen, std::int64_t base_classes, std::int64_t current_first,
                                       const DrawCounts& counts) {
  std::vector<torch::Tensor> features;
  std::vector<std::int64_t> labels;
  auto* extra = extra_draws_.data_ptr<std::int64_t>();
  for (std::int64_t c = 0; c < seen; ++c) {
    const bool in_session = c >= current_first;
    const std::int64_t cap = c < base_classes ? counts.base_cap : counts.old_cap;
    const std::int64_t n = in_session ? counts.current : std::min<std::int64_t>(cap, counts.regular + extra[c]);
    extra[c] = 0;
    if (n <= 0) continue;
    if (!factors_[c].defined()) factors_[c] = gaussian_factor(covariances_[c]);
    const torch::Tensor z = torch::randn({n, factors_[c].size(1)}, torch::kDouble);
    features.push_back((means_[c].to(torch::kDouble) + z.matmul(factors_[c].t())).to(torch::kFloat));
    labels.insert(labels.end(), n, c);
  }
  GaussianDraws draws;
  draws.features = features.empty() ? torch::zeros({0, means_.size(1)}) : torch::cat(features);
  draws.labels = torch::tensor(labels, torch::kLong);
  return draws;
}

}  // namespace fscil
