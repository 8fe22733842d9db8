#pragma once
#include <torch/torch.h>

#include <string>

#include "metrics/model_cost.h"

namespace fscil {

// LibTorch modules have no forward hooks, so costs are counted by walking our own modules with
// the input shape: each function reads the layer's sizes from the module itself, adds its cost
// for one sample (rules in metrics/model_cost.h) and returns the shape it outputs.
MapShape count_conv2d(ModelCost& cost, const std::string& name, const torch::nn::Conv2dImpl& conv,
                      const MapShape& input);
MapShape count_batch_norm(ModelCost& cost, const std::string& name, const torch::nn::BatchNorm2dImpl& norm,
                          const MapShape& input);
// Returns the output features.
std::int64_t count_linear(ModelCost& cost, const std::string& name, const torch::nn::LinearImpl& linear);
// Cosine logits of one embedding against `classes` rows; `parameters` are the rows the module holds.
void count_cosine_classifier(ModelCost& cost, const std::string& name, std::int64_t dim, std::int64_t classes,
                             const std::vector<torch::Tensor>& parameters);

// A layer entry of `kind` carrying the numel of `parameters`, split by requires_grad.
LayerCost layer_with_parameters(const std::string& name, const std::string& kind,
                                const std::vector<torch::Tensor>& parameters);

}  // namespace fscil
