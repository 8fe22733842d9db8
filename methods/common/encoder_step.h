#pragma once
#include <torch/torch.h>

#include <cstdint>

#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"

namespace fscil {

// The shared encoder's unit of work as the methods' base sessions do it, on one resident batch of
// random log-Mel maps: a training step (forward, backward and a Nesterov SGD step through
// ResNet-18 and a cosine classifier) and an inference pass (eval mode, no gradients). What the
// speed benchmarks, plan's calibration and the step profile time.
class EncoderStep {
 public:
  EncoderStep(std::int64_t channels, std::int64_t mel_bins, std::int64_t frames, std::int64_t batch,
              Precision precision = Precision::fp32, std::int64_t classes = 60);

  void train();
  void infer();  // switches the encoder to eval mode; train() switches it back
  ResNet18Encoder& encoder() { return encoder_; }

 private:
  std::int64_t classes_;
  ResNet18Encoder encoder_;
  CosineClassifier classifier_;
  torch::optim::SGD optimizer_;
  torch::Tensor features_, labels_;
};

}  // namespace fscil
