#include "methods/amfo/fusion_net.h"

namespace fscil {

FusionNetImpl::FusionNetImpl(std::int64_t classes, std::int64_t width) : classes_(classes) {
  hidden = register_module("hidden", torch::nn::Linear(2 * classes, width));
  out = register_module("out", torch::nn::Linear(width, 2));
}

torch::Tensor FusionNetImpl::forward(const torch::Tensor& inputs) { return out->forward(torch::relu(hidden->forward(inputs))); }

Fusion fuse(FusionNetImpl& net, const torch::Tensor& positive, const torch::Tensor& negative) {
  Fusion fusion;
  fusion.binary = net.forward(torch::cat({torch::softmax(positive, 1), torch::softmax(negative, 1)}, 1));
  const torch::Tensor weights = torch::softmax(fusion.binary, 1);
  fusion.mixed = weights.slice(1, 0, 1) * positive + weights.slice(1, 1, 2) * negative;
  return fusion;
}

FusionSlotImpl::FusionSlotImpl(std::int64_t classes, std::int64_t width) : width_(width) {
  net_ = register_module("net", FusionNet(classes, width_));
}

void FusionSlotImpl::replace(std::int64_t classes) { net_ = replace_module("net", FusionNet(classes, width_)); }

}  // namespace fscil
