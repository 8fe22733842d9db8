#include "methods/ldc/calibration_unit.h"

namespace fscil {

namespace F = torch::nn::functional;

CalibrationUnitImpl::CalibrationUnitImpl(std::int64_t dim) {
  const auto layer = torch::nn::LinearOptions(dim, dim).bias(false);
  first_ = register_module("layer1", torch::nn::Linear(layer));
  second_ = register_module("layer2", torch::nn::Linear(layer));
  third_ = register_module("layer4", torch::nn::Linear(layer));
}

std::vector<torch::Tensor> CalibrationUnitImpl::updates(torch::Tensor features, int rounds) {
  std::vector<torch::Tensor> out;
  for (int round = 0; round < rounds; ++round) {
    features = torch::relu(third_(torch::relu(second_(torch::relu(first_(features))))));
    out.push_back(features);
  }
  return out;
}

torch::Tensor calibration_loss(const std::vector<torch::Tensor>& updates, const torch::Tensor& real) {
  const torch::Tensor target = real.softmax(-1);
  torch::Tensor loss = torch::zeros({}, real.options());
  for (const torch::Tensor& update : updates) {
    loss = loss + F::kl_div(update.log_softmax(-1), target, F::KLDivFuncOptions().reduction(torch::kSum));
  }
  return loss;
}

}  // namespace fscil
