#include "methods/common/unrolled_convolution.h"

namespace fscil {

namespace {

// 0 when the window does not fit the padded map (integer division alone would round that up to 1).
std::int64_t output_size(std::int64_t size, std::int64_t kernel, std::int64_t stride, std::int64_t padding) {
  const std::int64_t room = size + 2 * padding - kernel;
  return room < 0 ? 0 : room / stride + 1;
}

// taps[t][p][q] = 1 where the window of output position q reads input position p with tap t:
// the 0/1 tensor that turns the weights into the unrolled matrix.
torch::Tensor tap_selection(std::int64_t height, std::int64_t width, std::int64_t kernel, std::int64_t stride,
                            std::int64_t padding) {
  const std::int64_t out_height = output_size(height, kernel, stride, padding);
  const std::int64_t out_width = output_size(width, kernel, stride, padding);
  torch::Tensor taps = torch::zeros({kernel * kernel, height * width, out_height * out_width}, torch::kFloat);
  auto at = taps.accessor<float, 3>();
  for (std::int64_t oy = 0; oy < out_height; ++oy) {
    for (std::int64_t ox = 0; ox < out_width; ++ox) {
      for (std::int64_t ky = 0; ky < kernel; ++ky) {
        for (std::int64_t kx = 0; kx < kernel; ++kx) {
          const std::int64_t iy = oy * stride - padding + ky, ix = ox * stride - padding + kx;
          if (iy >= 0 && iy < height && ix >= 0 && ix < width) at[ky * kernel + kx][iy * width + ix][oy * out_width + ox] = 1;
        }
      }
    }
  }
  return taps;
}

}  // namespace

torch::Tensor unrolled_conv2d(const torch::Tensor& input, const torch::Tensor& weight, std::int64_t stride,
                              std::int64_t padding) {
  const std::int64_t batch = input.size(0), in_channels = input.size(1), height = input.size(2), width = input.size(3);
  const std::int64_t out_channels = weight.size(0), kernel = weight.size(2);
  TORCH_CHECK(weight.size(1) == in_channels && weight.size(3) == kernel, "unrolled_conv2d: a square kernel over all input channels");
  const torch::Tensor taps = tap_selection(height, width, kernel, stride, padding).to(weight.options());
  const std::int64_t positions = height * width, out_positions = taps.size(2);
  // unrolled[(i, p), (o, q)] = sum_t weight[o, i, t] * taps[t, p, q]: input channel i at position
  // p feeds output channel o at position q, rows and columns in the maps' own (NCHW) order.
  const torch::Tensor products =
      weight.reshape({out_channels * in_channels, kernel * kernel}).mm(taps.view({kernel * kernel, -1}));
  const torch::Tensor unrolled = products.view({out_channels, in_channels, positions, out_positions})
                                     .permute({1, 2, 0, 3})
                                     .reshape({in_channels * positions, out_channels * out_positions});
  const torch::Tensor flat = input.reshape({batch, in_channels * positions});
  return flat.mm(unrolled).view({batch, out_channels, output_size(height, kernel, stride, padding),
                   output_size(width, kernel, stride, padding)});
}

bool unrolling_pays(std::int64_t height, std::int64_t width, std::int64_t kernel, std::int64_t stride,
                    std::int64_t padding) {
  const std::int64_t out_height = output_size(height, kernel, stride, padding);
  const std::int64_t out_width = output_size(width, kernel, stride, padding);
  return out_height >= 1 && out_width >= 1 && out_height * out_width <= 2 && height * width <= kernel * kernel;
}

}  // namespace fscil
