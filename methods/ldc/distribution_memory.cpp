#include "methods/ldc/distribution_memory.h"

#include "methods/common/class_statistics.h"

namespace fscil {

DistributionMemoryImpl::DistributionMemoryImpl(std::int64_t classes, std::int64_t kept_per_class, std::int64_t dim) {
  covariance_ = register_buffer("covariance", torch::zeros({dim, dim}));
  kept_ = register_buffer("kept", torch::zeros({classes, kept_per_class, dim}));
  removed_ = register_buffer("removed", torch::zeros({classes}, torch::kBool));
  unit_scale_ = register_buffer("unit_scale", torch::ones({}));
}

void DistributionMemoryImpl::start_covariance(const torch::Tensor& base_covariances) {
  covariance_.copy_(base_covariances.mean(0));
}

void DistributionMemoryImpl::fold_covariances(const torch::Tensor& session_covariances, std::int64_t base_classes) {
  const double n = static_cast<double>(session_covariances.size(0)), base = static_cast<double>(base_classes);
  for (std::int64_t c = 0; c < session_covariances.size(0); ++c) {
    covariance_.copy_((covariance_ * base + session_covariances[c] * n) / (base + n));
  }
}

torch::Tensor DistributionMemoryImpl::draw(const torch::Tensor& means, std::int64_t count) const {
  const torch::Tensor factor = gaussian_factor(covariance_);
  const torch::Tensor z = torch::randn({means.size(0), count, factor.size(1)}, torch::kDouble);
  return (means.to(torch::kDouble).unsqueeze(1) + z.matmul(factor.t())).to(torch::kFloat);
}

void DistributionMemoryImpl::keep(std::int64_t first, const torch::Tensor& draws) {
  kept_.slice(0, first, first + draws.size(0)).copy_(draws.slice(1, 0, kept_.size(1)));
}

void DistributionMemoryImpl::forget(const std::vector<std::int64_t>& classes) {
  for (std::int64_t c : classes) removed_[c] = true;
}

torch::Tensor DistributionMemoryImpl::kept_features(std::int64_t seen) const {
  return kept_.slice(0, 0, seen).index({present(seen)}).reshape({-1, kept_.size(2)});
}

torch::Tensor DistributionMemoryImpl::kept_labels(std::int64_t seen) const {
  return torch::arange(seen).index({present(seen)}).repeat_interleave(kept_.size(1));
}

}  // namespace fscil
