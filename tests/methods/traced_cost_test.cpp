#include "methods/common/traced_cost.h"

#include <gtest/gtest.h>

#include "methods/common/resnet18.h"

namespace fscil {
namespace {

TEST(TracedCost, CountsConvolutionsWithTheirBiasAndMatrixProductsByOurRules) {
  torch::nn::Conv2d conv(torch::nn::Conv2dOptions(4, 6, 3).padding(1).groups(2).bias(true));
  torch::nn::Linear linear(6, 5);
  linear->weight.set_requires_grad(false);
  const ModelCost cost = traced_cost(
      [&] { linear(torch::adaptive_avg_pool2d(conv(torch::zeros({1, 4, 5, 5})), {1, 1}).flatten(1)); },
      {{"conv", conv.ptr()}, {"linear", linear.ptr()}});
  EXPECT_EQ(cost.macs_of("conv"), 2'850);  // 150 outputs x (2 x 9 + 1), as count_conv2d counts it
  EXPECT_EQ(cost.macs_of("pool"), 150);    // every input element of the global average
  EXPECT_EQ(cost.macs_of("linear"), 30);   // 6 x 5, the bias not counted (thop's rule)
  EXPECT_EQ(cost.macs(), 2'850 + 150 + 30);
  EXPECT_EQ(cost.parameters(), 114 + 35);
  EXPECT_EQ(cost.trainable_parameters(), 114 + 5);  // the frozen weight is not trainable
}

TEST(TracedCost, AgreesWithTheWalkOfResNet18ExceptWhatRunsAsElementWiseOperations) {
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
  EXPECT_EQ(traced.macs_of("pool"), 256 * 2 * 1);  // the global average; the max pool's 55 296 are not seen
  EXPECT_EQ(walked.macs_of("pool") - traced.macs_of("pool"), 64 * 16 * 6 * 9);
  EXPECT_EQ(traced.parameters(), walked.parameters());
}

TEST(TracedCost, AForwardThatThrowsLeavesNoProfilerRunning) {
  EXPECT_THROW(traced_cost([] { throw std::runtime_error("bad forward"); }, {}), std::runtime_error);
  torch::nn::Linear linear(3, 2);
  EXPECT_EQ(traced_cost([&] { linear(torch::zeros({1, 3})); }, {}).macs(), 6);
}

}  // namespace
}  // namespace fscil
