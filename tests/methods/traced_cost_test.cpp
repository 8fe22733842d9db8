#include "methods/common/traced_cost.h"

#include <gtest/gtest.h>

#include "methods/common/resnet18.h"

namespace fscil {
namespace {

TEST(TracedCost, CountsConvolutionsWithTheirBiasAndMatrixProductsByOurRules) {
  torch::nn::Conv2d conv(torch::nn::Conv2dOptions(4, 6, 3).padding(1).groups(2).bias(true));
  torch::nn::Linear linear(6, 5);
  const ModelCost cost = traced_cost(
      [&] { linear(torch::adaptive_avg_pool2d(conv(torch::zeros({1, 4, 5, 5})), {1, 1}).flatten(1)); },
      {{"conv", conv.ptr(), /*trained_in_sessions=*/true}, {"linear", linear.ptr()}});
  EXPECT_EQ(cost.macs_of("conv"), 2'850);  // 150 outputs x (2 x 9 + 1), as count_conv2d counts it
  EXPECT_EQ(cost.macs_of("pool"), 150);    // every input element of the global average
  EXPECT_EQ(cost.macs_of("linear"), 30);   // 6 x 5, the bias not counted (thop's rule)
  EXPECT_EQ(cost.macs(), 2'850 + 150 + 30);
  EXPECT_EQ(cost.parameters(), 114 + 35);
  EXPECT_EQ(cost.trainable_parameters(), 114);  // the modules sessions train
}

TEST(TracedCost, AgreesWithTheWalkOfResNet18ExceptANormRunAsElementWiseOperations) {
  ResNet18Encoder encoder(ResNet18Options{5, 64});
  encoder->eval();
  ModelCost walked;
  encoder->count_cost(walked, "encoder", {5, 64, 24});
  const ModelCost traced = traced_cost([&] { encoder->forward(torch::zeros({1, 5, 64, 24})); }, {{"encoder", encoder.ptr()}});
  // In eval mode the stem's norm is folded into its convolution (the norm's 1 per element becomes
  // the folded bias's 1 per output), and bn0 runs as a broadcast scale and shift, which the trace
  // counts as element-wise: 5 x 64 x 24 MACs it does not see.
  EXPECT_EQ(traced.macs_of("conv") + traced.macs_of("batch_norm"),
            walked.macs_of("conv") + walked.macs_of("batch_norm") - 5 * 64 * 24);
  EXPECT_EQ(traced.macs_of("pool"), walked.macs_of("pool"));  // the max pool's windows and the global average
  EXPECT_EQ(traced.parameters(), walked.parameters());
}

TEST(TracedCost, CountsEachProductOnceWhateverCallsItAndConvolutionsOfAnyPadding) {
  torch::nn::Linear linear(6, 5);
  const auto macs_of = [](const std::function<void()>& forward) { return traced_cost(forward, {}).macs(); };
  EXPECT_EQ(macs_of([&] { linear(torch::zeros({1, 6})); }), 30);           // addmm
  EXPECT_EQ(macs_of([&] { linear(torch::zeros({1, 4, 6})); }), 4 * 30);    // matmul over a folded batch
  EXPECT_EQ(macs_of([] { torch::matmul(torch::zeros({3, 6}), torch::zeros({6})); }), 18);  // mv
  EXPECT_EQ(macs_of([] { torch::einsum("bij,bjk->bik", {torch::zeros({2, 3, 6}), torch::zeros({2, 6, 4})}); }),
            2 * 3 * 4 * 6);
  EXPECT_EQ(macs_of([] { torch::cdist(torch::zeros({3, 6}), torch::zeros({5, 6})); }), 3 * 5 * 6);
  torch::nn::Conv2d same(torch::nn::Conv2dOptions(2, 4, 3).padding(torch::kSame).bias(false));
  EXPECT_EQ(macs_of([&] { same(torch::zeros({1, 2, 5, 5})); }), 100 * 18);  // 4 x 5 x 5 outputs x 2 x 9
  torch::nn::Conv1d conv1d(torch::nn::Conv1dOptions(2, 4, 3).bias(false));
  EXPECT_EQ(macs_of([&] { conv1d(torch::zeros({1, 2, 10})); }), 4 * 8 * 6);
  torch::nn::ConvTranspose2d up(torch::nn::ConvTranspose2dOptions(2, 4, 2).stride(2).bias(false));
  EXPECT_EQ(macs_of([&] { up(torch::zeros({1, 2, 3, 3})); }), 2 * 3 * 3 * (4 * 4));  // every input into 4 x 2 x 2
  EXPECT_EQ(macs_of([] { torch::max_pool2d(torch::zeros({1, 3, 8, 8}), 3, 2, 1); }), 3 * 4 * 4 * 9);
}

TEST(TracedCost, AForwardThatThrowsLeavesNoTraceRunning) {
  EXPECT_THROW(traced_cost([] { throw std::runtime_error("bad forward"); }, {}), std::runtime_error);
  torch::nn::Linear linear(3, 2);
  EXPECT_EQ(traced_cost([&] { linear(torch::zeros({1, 3})); }, {}).macs(), 6);
}

}  // namespace
}  // namespace fscil
