#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace fscil {

// LDC's parameterized calibration unit (PCU) as the release codes it (Bibikiller/LDC Network.py
// L55-L71 at 4548445c): three Linear(D, D, no bias) + ReLU layers (layer1, layer2, layer4), applied
// again and again to the features they output, each pass one of the paper's recurrent updates
// (helper.py L76-L79, Network.py L220-L223). The layers' Dropout2d(0.5) never acts in the release:
// helper.py's test() puts the model in eval mode, inc_trainer.py calls it after replace_base_fc
// (L131-L134) and before the PCU trains (L137-L138), and no later step sets train mode back; so
// none is here.
class CalibrationUnitImpl : public torch::nn::Module {
 public:
  explicit CalibrationUnitImpl(std::int64_t dim);
  // The features after each of `rounds` updates (N x D each), the last the calibrated ones.
  std::vector<torch::Tensor> updates(torch::Tensor features, int rounds);

 private:
  torch::nn::Linear first_{nullptr}, second_{nullptr}, third_{nullptr};
};
TORCH_MODULE(CalibrationUnit);

// The release's distribution-matching loss for one class (dis_match, helper.py L68-L83): the sum
// over the updates of KL(softmax(real) || softmax(update)), each row of drawn features paired with
// the real feature of the same row, summed over rows and dimensions.
torch::Tensor calibration_loss(const std::vector<torch::Tensor>& updates, const torch::Tensor& real);

}  // namespace fscil
