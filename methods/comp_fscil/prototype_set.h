#pragma once
#include <torch/torch.h>

#include <cstdint>

namespace fscil {

// Classes' prototypes for Comp-FSCIL's two heads (models/base/Network.py L42, L49-L51 at
// 95a44177): a vector row (D) for the pooled embedding and a map prototype (D x h x w, one
// primitive per position of the encoder's last map), with PyTorch's default initialisations.
class PrototypeSetImpl : public torch::nn::Module {
 public:
  PrototypeSetImpl(std::int64_t classes, std::int64_t dim, std::int64_t height, std::int64_t width);
  torch::Tensor rows, maps;
};
TORCH_MODULE(PrototypeSet);

// The CKA head's learned scale tau (Network.py L53-L57): a scalar parameter.
class LearnedScaleImpl : public torch::nn::Module {
 public:
  explicit LearnedScaleImpl(double start);
  torch::Tensor value;
};
TORCH_MODULE(LearnedScale);

}  // namespace fscil
