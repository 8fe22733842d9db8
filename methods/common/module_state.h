#pragma once
#include <torch/torch.h>

#include <string>

#include "methods/method.h"

namespace fscil {

// A module's parameters and buffers into `state` under `prefix` (copies, detached).
void put_module(MethodState& state, const std::string& prefix, const torch::nn::Module& module);
// Copies them back into a module of the same architecture; MethodError when one is missing or
// shaped differently.
void take_module(const MethodState& state, const std::string& prefix, torch::nn::Module& module);
// One entry; MethodError when missing.
const torch::Tensor& take(const MethodState& state, const std::string& key);

}  // namespace fscil
