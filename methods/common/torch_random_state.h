#pragma once
#include <torch/torch.h>

#include <mutex>

namespace fscil {

// LibTorch's global CPU generator (randn, randint, dropout, initialisation), as a byte tensor.
inline torch::Tensor torch_random_state() {
  auto generator = at::detail::getDefaultCPUGenerator();
  std::lock_guard<std::mutex> lock(generator.mutex());
  return generator.get_state();
}

inline void restore_torch_random_state(const torch::Tensor& state) {
  auto generator = at::detail::getDefaultCPUGenerator();
  std::lock_guard<std::mutex> lock(generator.mutex());
  generator.set_state(state);
}

}  // namespace fscil
