#include "methods/common/module_state.h"

#include <fmt/format.h>

namespace fscil {

void put_module(MethodState& state, const std::string& prefix, const torch::nn::Module& module) {
  for (const auto& item : module.named_parameters()) state[prefix + item.key()] = item.value().detach().clone();
  for (const auto& item : module.named_buffers()) state[prefix + item.key()] = item.value().detach().clone();
}

void take_module(const MethodState& state, const std::string& prefix, torch::nn::Module& module) {
  torch::NoGradGuard no_grad;
  const auto restore = [&](const std::string& name, torch::Tensor& target) {
    const torch::Tensor& saved = take(state, prefix + name);
    if (saved.sizes() != target.sizes()) {
      throw MethodError(fmt::format("state '{}{}' has shape {}, the model expects {}", prefix, name,
                                    fmt::join(saved.sizes(), "x"), fmt::join(target.sizes(), "x")));
    }
    target.copy_(saved);
  };
  for (auto& item : module.named_parameters()) restore(item.key(), item.value());
  for (auto& item : module.named_buffers()) restore(item.key(), item.value());
}

const torch::Tensor& take(const MethodState& state, const std::string& key) {
  const auto found = state.find(key);
  if (found == state.end()) throw MethodError(fmt::format("state has no '{}'", key));
  return found->second;
}

}  // namespace fscil
