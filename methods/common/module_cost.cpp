#include "methods/common/module_cost.h"

namespace fscil {

LayerCost layer_with_parameters(const std::string& name, const std::string& kind,
                                const std::vector<torch::Tensor>& parameters) {
  LayerCost layer{name, kind};
  for (const auto& parameter : parameters) {
    layer.parameters += parameter.numel();
    if (parameter.requires_grad()) layer.trainable_parameters += parameter.numel();
  }
  return layer;
}

MapShape count_conv2d(ModelCost& cost, const std::string& name, const torch::nn::Conv2dImpl& conv,
                      const MapShape& input) {
  const auto& options = conv.options;
  const auto kernel = *options.kernel_size();
  const auto stride = *options.stride();
  const auto dilation = *options.dilation();
  const auto* explicit_padding = c10::get_if<torch::ExpandingArray<2>>(&options.padding());
  TORCH_CHECK(explicit_padding != nullptr, "cost counting expects explicit padding at ", name);
  const auto padding = **explicit_padding;
  TORCH_CHECK(padding[0] == padding[1] && stride[0] == stride[1] && dilation[0] == 1 &&
                  dilation[1] == 1 && input.channels == options.in_channels(),
              "cost counting expects square padding and stride, no dilation and ", options.in_channels(),
              " input channels at ", name);
  const MapShape output = window_output(input, options.out_channels(), kernel[0], kernel[1], stride[0], padding[0]);
  LayerCost layer = layer_with_parameters(name, "conv", conv.parameters());
  layer.macs = conv2d_macs(output, options.in_channels() / options.groups(), kernel[0], kernel[1], options.bias());
  cost.add(std::move(layer));
  return output;
}

MapShape count_batch_norm(ModelCost& cost, const std::string& name, const torch::nn::BatchNorm2dImpl& norm,
                          const MapShape& input) {
  LayerCost layer = layer_with_parameters(name, "batch_norm", norm.parameters());
  layer.macs = batch_norm_macs(input);
  cost.add(std::move(layer));
  return input;
}

std::int64_t count_linear(ModelCost& cost, const std::string& name, const torch::nn::LinearImpl& linear) {
  LayerCost layer = layer_with_parameters(name, "linear", linear.parameters());
  layer.macs = linear_macs(linear.options.in_features(), linear.options.out_features());
  cost.add(std::move(layer));
  return linear.options.out_features();
}

void count_cosine_classifier(ModelCost& cost, const std::string& name, std::int64_t dim, std::int64_t classes,
                             const std::vector<torch::Tensor>& parameters) {
  LayerCost layer = layer_with_parameters(name, "cosine", parameters);
  layer.macs = cosine_classifier_macs(dim, classes);
  cost.add(std::move(layer));
}

}  // namespace fscil
