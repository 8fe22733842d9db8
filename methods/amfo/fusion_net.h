#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// AMFO's fusion module, the release's BinaryNet (models/binary_net.py L8-L21 at f86d0844): the
// softmaxes of the two heads' cosines over C classes, concatenated (2C), through 2C -> 64 -> ReLU
// -> 2 with biases, PyTorch's default initialisation. Its two outputs say "base" and "novel".
class FusionNetImpl : public torch::nn::Module {
 public:
  FusionNetImpl(std::int64_t classes, std::int64_t width);
  torch::Tensor forward(const torch::Tensor& inputs);
  std::int64_t classes() const { return classes_; }

  torch::nn::Linear hidden{nullptr}, out{nullptr};

 private:
  std::int64_t classes_;
};
TORCH_MODULE(FusionNet);

// The fused scores (train.py L125-L132, Inc_train.py L439-L446): w = softmax(b), b the net's two
// logits on [softmax(positive), softmax(negative)] of the unscaled cosines (deep head first), and
// mixed = w_0 x positive + w_1 x negative per sample. Nothing is detached.
struct Fusion {
  torch::Tensor mixed;   // rows x classes, the cosines' scale
  torch::Tensor binary;  // rows x 2, b before any softmax
};
Fusion fuse(FusionNetImpl& net, const torch::Tensor& positive, const torch::Tensor& negative);

// The fusion net a base session or a session trains, replaced by a fresh one over all seen classes
// at the start of each session (Inc_train.py L343-L345). Holds it under the name "net".
class FusionSlotImpl : public torch::nn::Module {
 public:
  FusionSlotImpl(std::int64_t classes, std::int64_t width);
  void replace(std::int64_t classes);
  FusionNetImpl& net() { return *net_; }

 private:
  std::int64_t width_;
  FusionNet net_{nullptr};
};
TORCH_MODULE(FusionSlot);

}  // namespace fscil
