#pragma once
#include <torch/torch.h>

#include "methods/common/module_state.h"

namespace fscil {

// A copy of a module's parameters and buffers that can be written back into it later.
class ParameterSnapshot {
 public:
  ParameterSnapshot() = default;
  explicit ParameterSnapshot(const torch::nn::Module& module) { put_module(tensors_, "", module); }

  bool empty() const { return tensors_.empty(); }
  // Every parameter and buffer by name, as saved.
  const MethodState& tensors() const { return tensors_; }

  void restore_into(torch::nn::Module& module) const { take_module(tensors_, "", module); }

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
  MethodState tensors_;
};

}  // namespace fscil
