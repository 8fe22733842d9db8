#pragma once
#include <torch/torch.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace fscil {

// While it lives, every BatchNorm2d of `module` (all the shared encoder has) updates its running
// statistics as if it saw each batch `times` times: momentum m becomes 1 - (1 - m)^times, and the
// batch counter, which a pass raises by one, is raised by `times` - 1 more when the guard ends.
// Meant around one training-mode pass. A BatchNorm that keeps a cumulative average (no momentum)
// is left as it is.
class RepeatedBatchStatistics {
 public:
  RepeatedBatchStatistics(torch::nn::Module& module, int times) : times_(times) {
    for (const auto& child : module.modules()) {
      auto norm = std::dynamic_pointer_cast<torch::nn::BatchNorm2dImpl>(child);
      if (!norm || !norm->options.momentum().has_value()) continue;
      const double momentum = *norm->options.momentum();
      saved_.emplace_back(norm, momentum);
      norm->options.momentum(1.0 - std::pow(1.0 - momentum, times));
    }
  }
  ~RepeatedBatchStatistics() {
    torch::NoGradGuard no_grad;
    for (auto& [norm, momentum] : saved_) {
      norm->options.momentum(momentum);
      if (norm->is_training() && norm->options.track_running_stats()) norm->num_batches_tracked.add_(times_ - 1);
    }
  }
  RepeatedBatchStatistics(const RepeatedBatchStatistics&) = delete;
  RepeatedBatchStatistics& operator=(const RepeatedBatchStatistics&) = delete;

 private:
  int times_;
  std::vector<std::pair<std::shared_ptr<torch::nn::BatchNorm2dImpl>, double>> saved_;
};

}  // namespace fscil
