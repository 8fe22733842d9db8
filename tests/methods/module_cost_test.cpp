#include "methods/common/module_cost.h"

#include <gtest/gtest.h>

#include "methods/method_registry.h"
#include "methods/common/resnet18.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

std::int64_t numel_of(const std::vector<torch::Tensor>& tensors) {
  std::int64_t total = 0;
  for (const auto& tensor : tensors) total += tensor.numel();
  return total;
}

TEST(ModuleCost, ConvAndNormReadTheirSizesFromTheModule) {
  torch::nn::Conv2d conv(torch::nn::Conv2dOptions(4, 6, 3).padding(1).groups(2).bias(true));
  ModelCost cost;
  const MapShape output = count_conv2d(cost, "conv", *conv, {4, 5, 5});
  EXPECT_EQ(output.channels, 6);
  EXPECT_EQ(output.height, 5);
  EXPECT_EQ(cost.layers()[0].macs, 2'850);        // 150 outputs x (2 x 9 + 1)
  EXPECT_EQ(cost.layers()[0].parameters, 114);    // 6 x 2 x 9 weights + 6 biases
  torch::nn::BatchNorm2d norm(6);
  norm->weight.set_requires_grad(false);
  count_batch_norm(cost, "norm", *norm, output);
  EXPECT_EQ(cost.layers()[1].macs, 150);
  EXPECT_EQ(cost.layers()[1].parameters, 12);
  EXPECT_EQ(cost.layers()[1].trainable_parameters, 6);  // the frozen scale is not trainable
}

TEST(ModuleCost, ResNet18OnHapTexMatchesTheHandCountLayerByLayer) {
  ResNet18Encoder encoder(ResNet18Options{5, 64});
  ModelCost cost;
  encoder->count_cost(cost, "encoder", {5, 64, 24});
  // Convolutions: stem 6 021 120; stage 1 (16x6) 4 x 3 538 944; stage 2 (8x3) 1 769 472 +
  // 3 538 944 + 196 608 + 2 x 3 538 944; stage 3 (4x2) 2 359 296 + 4 718 592 + 262 144 +
  // 2 x 4 718 592; stage 4 (2x1) 1 179 648 x 4 + 131 072. thop's 54.4 M.
  EXPECT_EQ(cost.macs_of("conv"), 54'386'688);
  // Norms: bn0 7 680 + stem 24 576 + stage 1 4 x 6 144 + stages 2-4 5 x (3 072, 2 048, 512).
  EXPECT_EQ(cost.macs_of("batch_norm"), 84'992);
  // Pools: max pool 64x16x6 x 9 + the global average over 256x2x1.
  EXPECT_EQ(cost.macs_of("pool"), 55'808);
  EXPECT_EQ(cost.macs(), 54'386'688 + 84'992 + 55'808);
  EXPECT_EQ(cost.layers().size(), 1u + 2u + 1u + 8u * 4u + 3u * 2u + 1u);  // bn0, stem, maxpool, blocks, shortcuts, avgpool
  // Conv weights 5 209 408 + norm scales and shifts 7 168, and the walk misses none of them.
  EXPECT_EQ(cost.parameters(), 5'216'576);
  EXPECT_EQ(cost.parameters(), numel_of(encoder->parameters()));
  EXPECT_EQ(cost.trainable_parameters(), cost.parameters());
}

TEST(ModuleCost, ResNet18OnLmt108MatchesThop) {
  ResNet18Encoder encoder(ResNet18Options{3, 64});
  ModelCost cost;
  encoder->count_cost(cost, "encoder", {3, 64, 493});
  EXPECT_NEAR(static_cast<double>(cost.macs_of("conv")) / 1e6, 964.6, 0.05);
}

TEST(ModuleCost, CopFscilCostsPitsScPlusTheQuotientAdapter) {
  torch::manual_seed(3);
  ParameterSet params;
  params.set("pretrain_epochs", "1");
  params.set("pit_epochs", "0");
  auto pits_sc = create_method("pits-sc", params);
  auto cop_fscil = create_method("cop-fscil", params);
  for (auto* method : {pits_sc.get(), cop_fscil.get()}) {
    RunContext context = tiny_context(3);
    method->train_base(tiny_base(), context);
  }
  const InputShape input{2, 4, 4, 16};
  const ModelCost plain = pits_sc->inference_cost(input);
  const ModelCost probed = cop_fscil->inference_cost(input);
  // The cosine against the 6 base classes: 256 + 6 x 256; mu and sigma hold 10 x 256 each.
  EXPECT_EQ(plain.macs_of("cosine"), 1'792);
  EXPECT_EQ(plain.layers().back().parameters, 5'120);
  // PCQA: Linear(256, 256) + Linear(256, 8 x 256) + 16 reflection passes of 3 x 256.
  EXPECT_EQ(probed.macs() - plain.macs(), 65'536 + 524'288 + 12'288);
  EXPECT_EQ(probed.parameters() - plain.parameters(), (256 * 256 + 256) + (256 * 2048 + 2048));
  // Sessions fine-tune mu and sigma only, in both.
  EXPECT_EQ(plain.trainable_parameters(), 5'120);
  EXPECT_EQ(probed.trainable_parameters(), 5'120);
}

}  // namespace
}  // namespace fscil
