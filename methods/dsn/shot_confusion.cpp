#include "methods/dsn/shot_confusion.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"

namespace fscil {

ShotConfusion::ShotConfusion(std::int64_t base_classes, std::int64_t session_first, std::int64_t session_classes)
    : base_classes_(base_classes),
      session_first_(session_first),
      base_sums_(static_cast<std::size_t>(session_classes)),
      old_sums_(static_cast<std::size_t>(session_classes)),
      shots_(static_cast<std::size_t>(session_classes), 0) {}

void ShotConfusion::record(const torch::Tensor& cosines, const torch::Tensor& labels) {
  const torch::Tensor rows = cosines.detach();
  for (std::int64_t i = 0; i < rows.size(0); ++i) {
    const std::int64_t cls = labels[i].item<std::int64_t>(), local = cls - session_first_;
    const torch::Tensor own = rows[i].slice(0, cls, cls + 1);
    const torch::Tensor over_base = torch::softmax(torch::cat({rows[i].slice(0, 0, base_classes_), own}), 0);
    const torch::Tensor over_old = torch::softmax(torch::cat({rows[i].slice(0, 0, session_first_), own}), 0);
    auto& base_sum = base_sums_.at(local);
    auto& old_sum = old_sums_.at(local);
    base_sum = base_sum.defined() ? base_sum + over_base : over_base;
    old_sum = old_sum.defined() ? old_sum + over_old : over_old;
    ++shots_.at(local);
  }
}

torch::Tensor ShotConfusion::base_weights(std::int64_t cls) const {
  if (shots_.at(cls) == 0) throw MethodError(fmt::format("session class {} had no shot in an epoch to weigh its covariance by", cls));
  return base_sums_[cls] / static_cast<double>(shots_[cls]);
}

torch::Tensor ShotConfusion::old_weights(std::int64_t cls) const {
  if (shots_.at(cls) == 0) throw MethodError(fmt::format("session class {} had no shot in an epoch to weigh its covariance by", cls));
  return old_sums_[cls] / static_cast<double>(shots_[cls]);
}

torch::Tensor calibrated_covariance(const torch::Tensor& own, const torch::Tensor& weights,
                                    const torch::Tensor& base_covariances) {
  const std::int64_t base = base_covariances.size(0);
  return weights[base] * own + torch::tensordot(weights.slice(0, 0, base), base_covariances, {0}, {0});
}

std::vector<std::int64_t> confused_old_classes(const torch::Tensor& weights, int top_k) {
  const std::int64_t old = weights.size(0) - 1;
  const double floor = std::max(0.0, weights[old].item<double>());
  const torch::Tensor top = std::get<1>(weights.slice(0, 0, old).topk(std::min<std::int64_t>(top_k, old)));
  std::vector<std::int64_t> confused;
  for (std::int64_t i = 0; i < top.size(0); ++i) {
    const std::int64_t cls = top[i].item<std::int64_t>();
    if (weights[cls].item<double>() >= floor) confused.push_back(cls);
  }
  return confused;
}

}  // namespace fscil
