#pragma once
#include <torch/torch.h>

namespace fscil {

// conv2d (square kernel, no bias, dilation or groups) as one matrix product with the
// convolution's unrolled matrix, the form the encoder's training takes on the maps where oneDNN's
// kernels are slowest (`unrolling_pays`). Mathematically conv2d; the float rounding differs
// (another summation order), and depends on the batch's size as a matrix product's does.
torch::Tensor unrolled_conv2d(const torch::Tensor& input, const torch::Tensor& weight, std::int64_t stride,
                              std::int64_t padding);

// Whether a convolution with a `kernel` x `kernel` window that maps an input of `input_positions`
// to `output_positions` positions is faster unrolled: when the output map has at most two
// positions (HapTex's last stage, 2 x 1) and the unrolled product does no more multiply-adds
// than the convolution (input_positions <= kernel * kernel). Measured on a batch of 128 at
// 256 channels (docs/architecture.md, "The training step").
bool unrolling_pays(std::int64_t input_positions, std::int64_t output_positions, std::int64_t kernel);

}  // namespace fscil
