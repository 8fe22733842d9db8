#pragma once
#include <torch/torch.h>

#include <vector>

namespace fscil {

// Restores a module's buffers (batch-norm running statistics and counters) when it goes out of
// scope: for forwards in training mode whose batches must not shape the statistics used at
// test time, such as CoP-FSCIL's probe branch.
class RunningStatisticsGuard {
 public:
  explicit RunningStatisticsGuard(torch::nn::Module& module) : buffers_(module.buffers()) {
    for (const auto& buffer : buffers_) saved_.push_back(buffer.clone());
  }
  // Written through variable_data(), as batch norm's own update is: a graph built meanwhile
  // that saved these buffers stays valid.
  ~RunningStatisticsGuard() {
    for (std::size_t i = 0; i < buffers_.size(); ++i) buffers_[i].variable_data().copy_(saved_[i]);
  }
  RunningStatisticsGuard(const RunningStatisticsGuard&) = delete;
  RunningStatisticsGuard& operator=(const RunningStatisticsGuard&) = delete;

 private:
  std::vector<torch::Tensor> buffers_, saved_;
};

}  // namespace fscil
