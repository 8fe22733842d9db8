#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// The number of classes a method has seen, kept in a buffer so that a ModuleMethod's state
// (methods/module_method.h) holds it with the modules: "seen_classes.count" in checkpoints and
// --save-model files when listed as "seen_classes".
struct ClassCountImpl : torch::nn::Module {
  ClassCountImpl() : count(register_buffer("count", torch::zeros({}, torch::kLong))) {}
  std::int64_t value() const { return count.item<std::int64_t>(); }
  void add(std::int64_t classes) { count.add_(classes); }
  void reset() { count.zero_(); }
  torch::Tensor count;
};
TORCH_MODULE(ClassCount);

}  // namespace fscil
