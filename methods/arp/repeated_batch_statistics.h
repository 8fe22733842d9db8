#pragma once
#include <torch/torch.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace fscil {

// While it lives, every BatchNorm of `module` updates its running statistics as if it saw each
// batch `times` times: momentum m becomes 1 - (1 - m)^times.
class RepeatedBatchStatistics {
 public:
  RepeatedBatchStatistics(torch::nn::Module& module, int times) {
    for (const auto& child : module.modules()) {
      if (auto norm = std::dynamic_pointer_cast<torch::nn::BatchNorm2dImpl>(child)) {
        const double momentum = norm->options.momentum().value_or(0.1);
        saved_.emplace_back(norm, momentum);
        norm->options.momentum(1.0 - std::pow(1.0 - momentum, times));
      }
    }
  }
  ~RepeatedBatchStatistics() {
    for (auto& [norm, momentum] : saved_) norm->options.momentum(momentum);
  }
  RepeatedBatchStatistics(const RepeatedBatchStatistics&) = delete;
  RepeatedBatchStatistics& operator=(const RepeatedBatchStatistics&) = delete;

 private:
  std::vector<std::pair<std::shared_ptr<torch::nn::BatchNorm2dImpl>, double>> saved_;
};

}  // namespace fscil
