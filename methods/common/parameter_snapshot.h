#pragma once
#include <torch/torch.h>

#include <string>
#include <utility>
#include <vector>

namespace fscil {

// A copy of a module's parameters and buffers that can be written back into it later.
class ParameterSnapshot {
 public:
  ParameterSnapshot() = default;
  explicit ParameterSnapshot(const torch::nn::Module& module) {
    for (const auto& item : module.named_parameters()) tensors_.emplace_back(item.key(), item.value().detach().clone());
    for (const auto& item : module.named_buffers()) tensors_.emplace_back(item.key(), item.value().detach().clone());
  }

  bool empty() const { return tensors_.empty(); }
  // (name, saved copy) of every parameter and buffer.
  const std::vector<std::pair<std::string, torch::Tensor>>& tensors() const { return tensors_; }

  void restore_into(torch::nn::Module& module) const {
    torch::NoGradGuard no_grad;
    auto parameters = module.named_parameters();
    auto buffers = module.named_buffers();
    for (const auto& [name, saved] : tensors_) {
      torch::Tensor* target = parameters.find(name);
      if (target == nullptr) target = buffers.find(name);
      target->copy_(saved);
    }
  }

  // True when every saved tensor equals the module's current one exactly.
  bool matches(const torch::nn::Module& module) const {
    auto parameters = module.named_parameters();
    auto buffers = module.named_buffers();
    for (const auto& [name, saved] : tensors_) {
      const torch::Tensor* current = parameters.find(name);
      if (current == nullptr) current = buffers.find(name);
      if (current == nullptr || !torch::equal(*current, saved)) return false;
    }
    return true;
  }

 private:
  std::vector<std::pair<std::string, torch::Tensor>> tensors_;
};

}  // namespace fscil
