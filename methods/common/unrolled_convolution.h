#pragma once
#include <torch/torch.h>

namespace fscil {

// conv2d (square kernel, no bias, dilation or groups) as one matrix product with the
// convolution's unrolled matrix, the form the encoder's training takes on the maps where oneDNN's
// kernels are slowest (`unrolling_pays`). Mathematically conv2d; the float rounding differs
// (another summation order), and depends on the batch's size as a matrix product's does.
torch::Tensor unrolled_conv2d(const torch::Tensor& input, const torch::Tensor& weight, std::int64_t stride,
                              std::int64_t padding);

// Whether a zero-padded convolution with a `kernel` x `kernel` window and equal stride and padding
// in both axes is faster unrolled on a `height` x `width` map: when its output map has one or two
// positions (HapTex's last stage, 2 x 1) and the unrolled product does no more multiply-adds than
// the convolution counting the taps that read padding (height * width <= kernel * kernel). The
// bound of two positions is measured (docs/architecture.md, "The training step"): 2 x 1 maps
// gain 3-4x, 4 x 2 maps nothing.
bool unrolling_pays(std::int64_t height, std::int64_t width, std::int64_t kernel, std::int64_t stride,
                    std::int64_t padding);

}  // namespace fscil
