#include "metrics/model_cost.h"

#include <numeric>

namespace fscil {

void ModelCost::freeze(const std::string& prefix) {
  for (auto& layer : layers_) {
    if (layer.name.rfind(prefix, 0) == 0) layer.trainable_parameters = 0;
  }
}

std::int64_t ModelCost::macs() const {
  return std::accumulate(layers_.begin(), layers_.end(), std::int64_t{0},
                         [](std::int64_t sum, const LayerCost& layer) { return sum + layer.macs; });
}

std::int64_t ModelCost::macs_of(const std::string& kind) const {
  std::int64_t sum = 0;
  for (const auto& layer : layers_) {
    if (layer.kind == kind) sum += layer.macs;
  }
  return sum;
}

std::int64_t ModelCost::parameters() const {
  return std::accumulate(layers_.begin(), layers_.end(), std::int64_t{0},
                         [](std::int64_t sum, const LayerCost& layer) { return sum + layer.parameters; });
}

std::int64_t ModelCost::trainable_parameters() const {
  return std::accumulate(layers_.begin(), layers_.end(), std::int64_t{0},
                         [](std::int64_t sum, const LayerCost& layer) { return sum + layer.trainable_parameters; });
}

MapShape window_output(const MapShape& input, std::int64_t out_channels, std::int64_t kernel_h, std::int64_t kernel_w,
                       std::int64_t stride, std::int64_t padding) {
  return {out_channels, (input.height + 2 * padding - kernel_h) / stride + 1,
          (input.width + 2 * padding - kernel_w) / stride + 1};
}

std::int64_t conv2d_macs(const MapShape& output, std::int64_t in_channels_per_group, std::int64_t kernel_h,
                         std::int64_t kernel_w, bool bias) {
  return output.elements() * (in_channels_per_group * kernel_h * kernel_w + (bias ? 1 : 0));
}

std::int64_t linear_macs(std::int64_t in_features, std::int64_t out_features) { return in_features * out_features; }

std::int64_t batch_norm_macs(const MapShape& input) { return input.elements(); }

std::int64_t max_pool_macs(const MapShape& output, std::int64_t kernel) { return output.elements() * kernel * kernel; }

std::int64_t global_average_pool_macs(const MapShape& input) { return input.elements(); }

std::int64_t reflections_macs(std::int64_t dim, std::int64_t applications) { return 3 * dim * applications; }

std::int64_t cosine_classifier_macs(std::int64_t dim, std::int64_t classes) { return dim + dim * classes; }

}  // namespace fscil
