#pragma once
#include <torch/torch.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "methods/common/precision.h"
#include "metrics/memory_budget.h"
#include "metrics/model_cost.h"

namespace fscil {

struct ResNet18Options {
  std::int64_t in_channels = 1;
  std::int64_t mel_bins = 64;
  std::array<std::int64_t, 4> widths = {64, 128, 256, 256};  // PITS-SC narrows the last stage: D = 256
  // In eval mode, run each convolution and its batch norm as one convolution with folded weights
  // (same function up to float rounding, one pass over the activations instead of two).
  bool fold_norms_at_inference = true;
  // In training, keep only the input of the stem (with its pool) and of each of the four stages,
  // and run each again during backward (activation recomputation): the same gradients and
  // running statistics to the bit, for about one more forward pass of time and far less memory.
  bool recompute_activations = false;
  // With a budget (--max-memory), a training pass whose activations would take the process past
  // it recomputes them as above; the budget counts those passes.
  std::shared_ptr<MemoryBudget> memory_budget{};
  // bf16: the stem and the stages run under autocast to bfloat16 (methods/common/precision.h); every
  // map the encoder returns is fp32.
  Precision precision = Precision::fp32;
};

class BasicBlockImpl : public torch::nn::Module {
 public:
  BasicBlockImpl(std::int64_t in_planes, std::int64_t planes, std::int64_t stride, bool fold_norms_at_inference);
  torch::Tensor forward(const torch::Tensor& x);
  // Adds this block's inference cost for one sample; returns its output shape.
  MapShape count_cost(ModelCost& cost, const std::string& name, const MapShape& input) const;

 private:
  torch::nn::Conv2d conv1{nullptr}, conv2{nullptr};
  torch::nn::BatchNorm2d bn1{nullptr}, bn2{nullptr};
  torch::nn::Sequential downsample{nullptr};  // holds the two below, under PyTorch's names
  torch::nn::Conv2d shortcut_conv_{nullptr};
  torch::nn::BatchNorm2d shortcut_norm_{nullptr};
  bool fold_norms_at_inference_;
};
TORCH_MODULE(BasicBlock);

// A transform of the map right after the input norm bn0 (where PITS-SC's released code applies
// its augmentations; cop-fscil's CPI in standardised units). Empty = none.
using InputNormHook = std::function<torch::Tensor(const torch::Tensor&)>;

// torchvision-style ResNet-18 on C x n_mels x frames log-Mel input, preceded by PITS-SC's
// per-Mel-bin input BatchNorm ("bn0"); returns the globally pooled D-dimensional embedding.
class ResNet18EncoderImpl : public torch::nn::Module {
 public:
  explicit ResNet18EncoderImpl(const ResNet18Options& options);
  torch::Tensor forward(const torch::Tensor& x, const InputNormHook& after_input_norm = {});
  // The last stage's map before the global pooling, N x D x h x w: what forward() averages. With
  // `first_stage_map`, the first stage's output map (N x widths[0] x h1 x w1) is written there too.
  torch::Tensor forward_map(const torch::Tensor& x, const InputNormHook& after_input_norm = {},
                            torch::Tensor* first_stage_map = nullptr);
  // forward() and, beside it, the first stage's map pooled globally (N x widths[0]): AMFO's
  // shallow feature. The same embedding as forward().
  std::pair<torch::Tensor, torch::Tensor> forward_with_first_stage(const torch::Tensor& x);
  std::int64_t embedding_size() const { return embedding_size_; }
  // Adds the inference cost of one C x n_mels x frames sample, layer by layer.
  void count_cost(ModelCost& cost, const std::string& name, const MapShape& input) const;
  // Segment `segment` on its input, unfolded (training, or inference without folded norms): 0 is
  // the stem with its norm, ReLU and max pool, 1-4 the stages (two blocks each). Recomputation
  // works segment by segment.
  torch::Tensor run_segment(int segment, const torch::Tensor& x);
  // The segment's parameters that train.
  std::vector<torch::Tensor> segment_parameters(int segment) const;
  // Bytes a training pass adds from the stem's input `normalised` (bn0's output after the input
  // norm hook, N x C x n_mels x frames) on, unless it recomputes: what the stem and the four
  // stages keep for backward, and the two gradients of the stem's map that backward then holds.
  // Estimated from the shapes.
  std::int64_t training_pass_bytes(const torch::Tensor& normalised) const;

 private:
  torch::nn::BatchNorm2d input_norm{nullptr};
  torch::nn::Conv2d stem{nullptr};
  torch::nn::BatchNorm2d stem_norm{nullptr};
  torch::nn::Sequential stages{nullptr};
  std::array<std::int64_t, 4> widths_;
  std::int64_t embedding_size_;
  bool fold_norms_at_inference_;
  bool recompute_activations_;
  std::shared_ptr<MemoryBudget> memory_budget_;
  Precision precision_;
};
TORCH_MODULE(ResNet18Encoder);

struct RunContext;
// The shared encoder's options for the run's input (channels, Mel bins), recomputation and memory
// budget.
ResNet18Options encoder_options(const RunContext& context);

}  // namespace fscil
