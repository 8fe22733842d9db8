#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace fscil {

// What DSN measures of the current session's real shots over one epoch (exemplar.py L159-L179 at
// 6b6a9bc8, "Distribution"): per class, the mean of two softmaxes of each shot's unscaled cosines,
// one over [the base classes, its own class] and one over [every class seen before the session,
// its own class]. The first weighs the base covariances its covariance is calibrated with, the
// second picks the old classes that get one more draw.
class ShotConfusion {
 public:
  ShotConfusion(std::int64_t base_classes, std::int64_t session_first, std::int64_t session_classes);
  // `cosines`: rows x seen classes, as the model scores the shots (no temperature: ex L168-L172
  // gets `output`, not 16 x output, so the weights are close to uniform); `labels`: their classes.
  void record(const torch::Tensor& cosines, const torch::Tensor& labels);
  // The epoch's mean weights of session class `cls` (0-based within the session): B + 1 values,
  // then L + 1, the own class last. MethodError when the class had no shot.
  torch::Tensor base_weights(std::int64_t cls) const;
  torch::Tensor old_weights(std::int64_t cls) const;

 private:
  std::int64_t base_classes_, session_first_;
  std::vector<torch::Tensor> base_sums_, old_sums_;
  std::vector<std::int64_t> shots_;
};

// The calibrated covariance (ex L181-L188): w_own x own + sum_j w_j x base covariance j.
torch::Tensor calibrated_covariance(const torch::Tensor& own, const torch::Tensor& weights,
                                    const torch::Tensor& base_covariances);

// The old classes among the `top_k` of `weights`' first L entries whose weight reaches
// max(0, w_own), w_own being the last entry (ex L190-L197).
std::vector<std::int64_t> confused_old_classes(const torch::Tensor& weights, int top_k);

}  // namespace fscil
