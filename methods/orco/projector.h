#pragma once
#include <string>

#include "methods/common/module_cost.h"
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// OrCo's projection head: Linear(D, hidden), ReLU, Linear(hidden, P).
class ProjectorImpl : public torch::nn::Module {
 public:
  ProjectorImpl(std::int64_t input_size, std::int64_t hidden_size, std::int64_t output_size)
      : hidden(register_module("hidden", torch::nn::Linear(input_size, hidden_size))),
        output(register_module("output", torch::nn::Linear(hidden_size, output_size))) {}
  torch::Tensor forward(const torch::Tensor& x) { return output->forward(torch::relu(hidden->forward(x))); }
  // Returns the output size.
  std::int64_t count_cost(ModelCost& cost, const std::string& name) const {
    count_linear(cost, name + ".hidden", *hidden);
    return count_linear(cost, name + ".output", *output);
  }

 private:
  torch::nn::Linear hidden, output;
};
TORCH_MODULE(Projector);

}  // namespace fscil
