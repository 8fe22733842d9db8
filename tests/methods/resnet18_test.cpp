#include "methods/common/resnet18.h"

#include <gtest/gtest.h>

namespace fscil {
namespace {

// Two encoders with identical weights and running statistics, one folding its norms at inference.
struct EncoderPair {
  ResNet18Encoder folded{nullptr}, plain{nullptr};
};

EncoderPair encoder_pair() {
  torch::manual_seed(5);
  ResNet18Options options{3, 16};
  EncoderPair pair{ResNet18Encoder(options), nullptr};
  options.fold_norms_at_inference = false;
  pair.plain = ResNet18Encoder(options);
  torch::NoGradGuard no_grad;
  for (auto& item : pair.folded->named_parameters()) {
    item.value().uniform_(0.5, 1.5);  // norms away from the identity, so folding has work to do
    pair.plain->named_parameters()[item.key()].copy_(item.value());
  }
  for (auto& item : pair.folded->named_buffers()) {
    if (item.value().is_floating_point()) item.value().uniform_(0.2, 2.0);
    pair.plain->named_buffers()[item.key()].copy_(item.value());
  }
  return pair;
}

TEST(ResNet18, FoldedNormsAtInferenceGiveTheUnfoldedEmbedding) {
  EncoderPair pair = encoder_pair();
  pair.folded->eval();
  pair.plain->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({4, 3, 16, 20});
  const torch::Tensor folded = pair.folded->forward(x), plain = pair.plain->forward(x);
  EXPECT_GT(plain.abs().max().item<double>(), 1.0);
  EXPECT_TRUE(torch::allclose(folded, plain, 1e-4, 1e-4)) << (folded - plain).abs().max().item<double>();
}

TEST(ResNet18, TrainingModeIsUntouchedByFolding) {
  EncoderPair pair = encoder_pair();
  const torch::Tensor x = torch::randn({4, 3, 16, 20});
  EXPECT_TRUE(torch::equal(pair.folded->forward(x), pair.plain->forward(x)));
}

}  // namespace
}  // namespace fscil

namespace fscil {
namespace {

TEST(ResNet18, TheInputNormHookSeesBn0sStandardisedMapInBothModes) {
  EncoderPair pair = encoder_pair();
  torch::NoGradGuard no_grad;
  const torch::Tensor x = 40 + 10 * torch::randn({6, 3, 16, 20});  // dB-like levels
  torch::Tensor seen;
  const InputNormHook record = [&](const torch::Tensor& map) {
    seen = map.clone();
    return map;
  };
  // Training mode: bn0 standardises each Mel bin over the batch (then its weight and bias).
  pair.plain->train();
  pair.plain->forward(x, record);
  auto& bn0 = *pair.plain->named_modules()["bn0"]->as<torch::nn::BatchNorm2d>();
  const torch::Tensor per_bin = x.transpose(1, 2);  // Mel bins as channels, as bn0 sees them
  const torch::Tensor mean = per_bin.mean({0, 2, 3}, true), var = per_bin.var({0, 2, 3}, false, true);
  const torch::Tensor expected =
      ((per_bin - mean) / torch::sqrt(var + 1e-5) * bn0.weight.view({1, -1, 1, 1}) + bn0.bias.view({1, -1, 1, 1}))
          .transpose(1, 2);
  EXPECT_TRUE(torch::allclose(seen, expected, 1e-4, 1e-4));
  // Inference, folded or not: the map from the running statistics; an identity hook changes
  // nothing, another map (negated) changes the embedding.
  for (ResNet18Encoder* encoder : {&pair.folded, &pair.plain}) {
    (*encoder)->eval();
    auto& norm = *(*encoder)->named_modules()["bn0"]->as<torch::nn::BatchNorm2d>();
    const auto bins = [](const torch::Tensor& v) { return v.view({1, 1, -1, 1}); };
    const torch::Tensor at_inference =
        (x - bins(norm.running_mean)) / torch::sqrt(bins(norm.running_var) + 1e-5) * bins(norm.weight) +
        bins(norm.bias);
    const torch::Tensor plain = (*encoder)->forward(x);
    EXPECT_TRUE(torch::allclose((*encoder)->forward(x, record), plain, 1e-5, 1e-5));
    EXPECT_TRUE(torch::allclose(seen, at_inference, 1e-4, 1e-4));
  }
  // (The pair's all-positive weights saturate; a freshly initialised encoder does not.)
  ResNet18Encoder fresh(ResNet18Options{3, 16});
  fresh->eval();
  const torch::Tensor negated = fresh->forward(x, [](const torch::Tensor& map) { return -map; });
  EXPECT_FALSE(torch::allclose(negated, fresh->forward(x), 1e-3, 1e-3));
}

}  // namespace
}  // namespace fscil
