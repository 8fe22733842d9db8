#include "metrics/model_cost.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

// Every expected value below is worked out by hand in the comment beside it.

TEST(ModelCostRules, ConvolutionCountsOutputElementsTimesItsReceptiveField) {
  // ResNet-18's stem on a HapTex input: 5x64x24 -> 7x7 stride 2 pad 3 -> 64 x 32 x 12.
  const MapShape output = window_output({5, 64, 24}, 64, 7, 7, 2, 3);
  EXPECT_EQ(output.channels, 64);
  EXPECT_EQ(output.height, 32);  // (64 + 6 - 7) / 2 + 1
  EXPECT_EQ(output.width, 12);   // (24 + 6 - 7) / 2 + 1
  EXPECT_EQ(conv2d_macs(output, 5, 7, 7, false), 6'021'120);  // 64*32*12 = 24 576 outputs x 5*49
  // A grouped convolution with bias: 4 -> 6 channels in 2 groups, 3x3, on 5x5 padded 1:
  // 6*5*5 = 150 outputs x (2 input channels per group x 9 + 1 bias).
  EXPECT_EQ(conv2d_macs(window_output({4, 5, 5}, 6, 3, 3, 1, 1), 2, 3, 3, true), 2'850);
}

TEST(ModelCostRules, LinearNormPoolReflectionsAndCosine) {
  EXPECT_EQ(linear_macs(256, 2048), 524'288);                 // thop: in x out, bias not counted
  EXPECT_EQ(batch_norm_macs({64, 32, 12}), 24'576);           // 1 per element
  EXPECT_EQ(max_pool_macs({64, 16, 6}, 3), 55'296);           // 6 144 outputs x 9 reads
  EXPECT_EQ(global_average_pool_macs({256, 2, 1}), 512);      // every input element once
  EXPECT_EQ(reflections_macs(256, 16), 12'288);               // 8 reflections, Q then Q^T: 16 x 3 x 256
  EXPECT_EQ(cosine_classifier_macs(256, 15), 4'096);          // 256 (norm) + 15 x 256
}

TEST(ModelCost, TotalsAreTheSumsOfItsLayersAndFlopsTwiceTheMacs) {
  ModelCost cost;
  cost.add({"a", "conv", 1'000, 300, 300});
  cost.add({"b", "batch_norm", 20, 8, 0});
  cost.add({"c", "conv", 500, 100, 100});
  EXPECT_EQ(cost.macs(), 1'520);
  EXPECT_EQ(cost.flops(), 3'040);
  EXPECT_EQ(cost.macs_of("conv"), 1'500);
  EXPECT_EQ(cost.macs_of("pool"), 0);
  EXPECT_EQ(cost.parameters(), 408);
  EXPECT_EQ(cost.trainable_parameters(), 400);
  cost.freeze("c");
  EXPECT_EQ(cost.trainable_parameters(), 300);
  EXPECT_EQ(cost.parameters(), 408);
}

}  // namespace
}  // namespace fscil
