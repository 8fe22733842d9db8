#pragma once
#include <torch/torch.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "metrics/model_cost.h"

namespace fscil {

using NamedModules = std::vector<std::pair<std::string, std::shared_ptr<torch::nn::Module>>>;

// The inference cost of a forward pass no cost walker knows (module_cost.h walks ours), read from
// the autograd profiler's record of the ATen operations `forward` runs on one sample, by
// metrics/model_cost.h's rules: convolutions (with their bias), matrix products, batch norm, and
// adaptive average pooling over every input element. The profiler records no pooling window, so
// max pooling counts 0 (thop's rule, not ours); element-wise operations count 0, as ours do, and so
// does a norm a forward pass applies by hand as a broadcast scale and shift.
// `modules` give the parameters, trainable when they require gradients.
ModelCost traced_cost(const std::function<void()>& forward, const NamedModules& modules);

}  // namespace fscil
