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
