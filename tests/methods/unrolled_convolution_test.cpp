#include "methods/common/unrolled_convolution.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

struct ConvolutionCase {
  std::int64_t height, width, kernel, stride, padding;
};

// Values and both gradients (input, weight) of conv2d, to float rounding.
void expect_conv2d(const ConvolutionCase& c) {
  torch::manual_seed(3);
  const torch::Tensor input = torch::randn({5, 7, c.height, c.width}).requires_grad_();
  const torch::Tensor weight = torch::randn({6, 7, c.kernel, c.kernel}).requires_grad_();
  const torch::Tensor expected = torch::conv2d(input, weight, {}, c.stride, c.padding);
  const torch::Tensor unrolled = unrolled_conv2d(input, weight, c.stride, c.padding);
  ASSERT_EQ(unrolled.sizes(), expected.sizes());
  EXPECT_TRUE(torch::allclose(unrolled, expected, 1e-5, 1e-4)) << (unrolled - expected).abs().max().item<double>();
  const torch::Tensor upstream = torch::randn(expected.sizes());
  const std::vector<torch::Tensor> wrt{input, weight};
  const auto expected_gradients = torch::autograd::grad({expected}, wrt, {upstream});
  const auto gradients = torch::autograd::grad({unrolled}, wrt, {upstream});
  for (std::size_t i = 0; i < wrt.size(); ++i) {
    EXPECT_GT(expected_gradients[i].abs().max().item<double>(), 0.1);
    EXPECT_TRUE(torch::allclose(gradients[i], expected_gradients[i], 1e-5, 1e-4))
        << "gradient " << i << ": " << (gradients[i] - expected_gradients[i]).abs().max().item<double>();
  }
}

TEST(UnrolledConvolution, IsConv2dWithItsGradientsOnTinyMaps) {
  // HapTex's last stage (2 x 1, and its stride-2 entry from 4 x 2), and shapes with every tap
  // partly in the padding.
  for (const ConvolutionCase& c : {ConvolutionCase{2, 1, 3, 1, 1}, ConvolutionCase{4, 2, 3, 2, 1}, ConvolutionCase{1, 1, 3, 1, 1}, ConvolutionCase{3, 2, 3, 1, 1},
                        ConvolutionCase{2, 3, 3, 2, 1}, ConvolutionCase{4, 3, 1, 2, 0}, ConvolutionCase{5, 4, 3, 1, 0}}) {
    SCOPED_TRACE(testing::Message() << c.height << "x" << c.width << " k" << c.kernel << " s" << c.stride << " p" << c.padding);
    expect_conv2d(c);
  }
}

TEST(UnrolledConvolution, PaysOnlyOnOneOrTwoOutputPositionsWithoutExtraWork) {
  EXPECT_TRUE(unrolling_pays(2, 1, 3, 1, 1));   // HapTex's last stage: 2 x 1 to 2 x 1
  EXPECT_TRUE(unrolling_pays(4, 2, 3, 2, 1));   // its entry: 4 x 2 to 2 x 1, 8 <= 9 taps
  EXPECT_TRUE(unrolling_pays(3, 1, 3, 2, 1));   // 3 x 1 to 2 x 1
  EXPECT_FALSE(unrolling_pays(4, 2, 3, 1, 1));  // 4 x 2 to 4 x 2: oneDNN is as fast there
  EXPECT_FALSE(unrolling_pays(2, 3, 3, 1, 1));  // 2 x 3: three output positions
  EXPECT_FALSE(unrolling_pays(4, 2, 1, 2, 0));  // a 1 x 1 shortcut would do 8 times the work
  EXPECT_FALSE(unrolling_pays(5, 2, 3, 2, 1));  // 10 input positions > 9 taps
  EXPECT_FALSE(unrolling_pays(2, 2, 3, 1, 0));  // no output at all
  EXPECT_FALSE(unrolling_pays(2, 2, 3, 2, 0));  // none either, though integer division rounds to one
}

}  // namespace
}  // namespace fscil
