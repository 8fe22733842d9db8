#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace fscil {

// One sample's feature map: channels x height x width.
struct MapShape {
  std::int64_t channels = 0, height = 0, width = 0;
  std::int64_t elements() const { return channels * height * width; }
};

// Inference cost of one layer for one sample.
struct LayerCost {
  std::string name;  // the module's path, e.g. "encoder.stages.2.conv1"
  std::string kind;  // conv, linear, batch_norm, pool, reflections, cosine, attention, layer_norm
  std::int64_t macs = 0;
  std::int64_t parameters = 0;
  std::int64_t trainable_parameters = 0;  // parameters incremental sessions still train
};

// Multiply-accumulates (MACs) per sample at inference, layer by layer, and the parameters
// that produce them. FLOPs = 2 x MACs.
//
// Convention (per sample):
// - conv: output elements x (input channels / groups x kernel area + 1 if bias): thop's and
//   ptflops's rule;
// - linear: input features x output features: thop's rule (ptflops adds the bias: we do not);
// - batch norm: 1 per element, the folded scale-and-shift of inference (thop counts 2 per
//   element, 4 with affine parameters; ptflops 1, 2 with affine);
// - pooling: 1 per window element read: k x k per output for max pooling, every input element
//   for global average pooling (thop: 0 for max pooling, window + 1 per output for average);
// - Householder reflection x - 2 (v.x / v.v) v: 3 D per application (v.v, v.x and the update;
//   thop cannot see them);
// - cosine classifier: D to normalise the embedding plus D per seen class (rows normalised once;
//   rows that change with every sample, as after PAN's attention, add D per row);
// - attention over T tokens of width D: 2 T^2 D (the scores and the weighted sum; its
//   projections count as linear layers, once per token);
// - layer norm: 1 per element, as batch norm.
// ReLU, residual additions and the softmax are not counted (as in thop and ptflops).
class ModelCost {
 public:
  void add(LayerCost layer) { layers_.push_back(std::move(layer)); }
  // Marks the layers whose name starts with `prefix` as not trained in incremental sessions.
  void freeze(const std::string& prefix);
  const std::vector<LayerCost>& layers() const { return layers_; }

  std::int64_t macs() const;
  std::int64_t macs_of(const std::string& kind) const;
  std::int64_t flops() const { return 2 * macs(); }
  std::int64_t parameters() const;
  std::int64_t trainable_parameters() const;

 private:
  std::vector<LayerCost> layers_;
};

// Output map of a convolution or pooling window (PyTorch's floor rule, no dilation).
MapShape window_output(const MapShape& input, std::int64_t out_channels, std::int64_t kernel_h, std::int64_t kernel_w,
                       std::int64_t stride, std::int64_t padding);

std::int64_t conv2d_macs(const MapShape& output, std::int64_t in_channels_per_group, std::int64_t kernel_h,
                         std::int64_t kernel_w, bool bias);
std::int64_t linear_macs(std::int64_t in_features, std::int64_t out_features);
std::int64_t batch_norm_macs(const MapShape& input);
std::int64_t max_pool_macs(const MapShape& output, std::int64_t kernel);
std::int64_t global_average_pool_macs(const MapShape& input);
std::int64_t reflections_macs(std::int64_t dim, std::int64_t applications);
std::int64_t cosine_classifier_macs(std::int64_t dim, std::int64_t classes);

}  // namespace fscil
