#include "methods/common/resnet18.h"

#include <ATen/autocast_mode.h>
#include <gtest/gtest.h>
#include <malloc.h>

#include <set>
#include <vector>

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

TEST(ResNet18, AnEmbeddingAtInferenceDependsOnTheSamplesBesideItOnlyByRounding) {
  // HapTex's shape (the channels-last stem, the 2 x 1 maps). oneDNN picks its kernels by batch
  // size, so bit equality does not hold; the tolerance is the one prototypes are checked at.
  torch::manual_seed(6);
  for (const bool fold : {true, false}) {
    ResNet18Options options{5, 64};
    options.fold_norms_at_inference = fold;
    ResNet18Encoder encoder(options);
    encoder->eval();
    torch::NoGradGuard no_grad;
    const torch::Tensor batch = torch::randn({9, 5, 64, 24});
    const torch::Tensor together = encoder->forward(batch);
    for (const std::int64_t i : {0, 4, 8}) {
      const torch::Tensor alone = encoder->forward(batch.narrow(0, i, 1));
      EXPECT_TRUE(torch::allclose(alone, together.narrow(0, i, 1), 1e-4, 1e-5)) << fold << " " << i;
    }
  }
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

namespace fscil {
namespace {

// Two encoders with the same initial weights, the second recomputing its stem and stages in
// backward (always, or as its memory budget decides).
std::pair<ResNet18Encoder, ResNet18Encoder> recompute_pair(std::shared_ptr<MemoryBudget> budget = nullptr,
                                                          Precision precision = Precision::fp32) {
  ResNet18Options options{3, 16};
  options.precision = precision;
  torch::manual_seed(7);
  ResNet18Encoder kept(options);
  options.recompute_activations = budget == nullptr;
  options.memory_budget = budget;
  torch::manual_seed(7);
  ResNet18Encoder recomputed(options);
  return {kept, recomputed};
}

// Nodes of the graph behind `root` whose name contains `name`, each counted once.
int count_nodes(const std::shared_ptr<torch::autograd::Node>& root, const std::string& name) {
  std::set<const torch::autograd::Node*> seen;
  std::vector<const torch::autograd::Node*> pending{root.get()};
  int found = 0;
  while (!pending.empty()) {
    const torch::autograd::Node* node = pending.back();
    pending.pop_back();
    if (node == nullptr || !seen.insert(node).second) continue;
    if (node->name().find(name) != std::string::npos) ++found;
    for (const auto& edge : node->next_edges()) pending.push_back(edge.function.get());
  }
  return found;
}

bool graph_has(const std::shared_ptr<torch::autograd::Node>& node, const std::string& name) {
  return count_nodes(node, name) > 0;
}

// Three SGD steps on the same batches; every parameter, gradient and running statistic compared.
// What does not train in expect_identical_training: bn0 is the stem segment's input side, the stem
// convolution and its norm ("conv1", "bn1") its parameters.
enum class Frozen { nothing, input_norm, stem, input_norm_and_stem };

bool is_frozen(const std::string& name, Frozen frozen) {
  const bool input_norm = name.rfind("bn0.", 0) == 0;
  const bool stem = name.rfind("conv1.", 0) == 0 || name.rfind("bn1.", 0) == 0;
  switch (frozen) {
    case Frozen::nothing: return false;
    case Frozen::input_norm: return input_norm;
    case Frozen::stem: return stem;
    case Frozen::input_norm_and_stem: return input_norm || stem;
  }
  return false;
}

void expect_identical_training(ResNet18Encoder& kept, ResNet18Encoder& recomputed, Frozen frozen) {
  for (auto* encoder : {&kept, &recomputed}) {
    (*encoder)->train();
    for (auto& item : (*encoder)->named_parameters()) {
      if (is_frozen(item.key(), frozen)) item.value().requires_grad_(false);
    }
  }
  torch::optim::SGD kept_sgd(kept->parameters(), torch::optim::SGDOptions(0.1).momentum(0.9));
  torch::optim::SGD recomputed_sgd(recomputed->parameters(), torch::optim::SGDOptions(0.1).momentum(0.9));
  for (int step = 0; step < 3; ++step) {
    torch::manual_seed(100 + step);
    const torch::Tensor batch = torch::randn({6, 3, 16, 20}), target = torch::randn({6, 256});
    kept_sgd.zero_grad();
    recomputed_sgd.zero_grad();
    const torch::Tensor kept_out = kept->forward(batch), recomputed_out = recomputed->forward(batch);
    ASSERT_TRUE(torch::equal(kept_out, recomputed_out)) << "step " << step;
    // The stem (with its pool) and the four stages; a stem whose parameters and input both need
    // no gradient has no graph to recompute.
    EXPECT_EQ(count_nodes(recomputed_out.grad_fn(), "RecomputedSegment"),
              frozen == Frozen::input_norm_and_stem ? 4 : 5);
    EXPECT_FALSE(graph_has(kept_out.grad_fn(), "RecomputedSegment"));
    ((kept_out - target).pow(2).sum()).backward();
    ((recomputed_out - target).pow(2).sum()).backward();
    const auto recomputed_parameters = recomputed->named_parameters();
    for (const auto& item : kept->named_parameters()) {
      const torch::Tensor& other = recomputed_parameters[item.key()];
      ASSERT_EQ(item.value().grad().defined(), other.grad().defined()) << item.key();
      if (item.value().grad().defined()) {
        EXPECT_TRUE(torch::equal(item.value().grad(), other.grad())) << item.key() << ", step " << step;
      }
    }
    kept_sgd.step();
    recomputed_sgd.step();
    const auto recomputed_buffers = recomputed->named_buffers();
    for (const auto& item : kept->named_buffers()) {
      EXPECT_TRUE(torch::equal(item.value(), recomputed_buffers[item.key()])) << item.key() << " counted twice?";
    }
  }
  for (const auto& item : kept->named_parameters()) {
    EXPECT_TRUE(torch::equal(item.value(), recomputed->named_parameters()[item.key()])) << item.key();
  }
}

TEST(ResNet18, RecomputedSegmentsTrainToTheBitLikeKeptActivations) {
  auto [kept, recomputed] = recompute_pair();
  expect_identical_training(kept, recomputed, Frozen::nothing);
}

TEST(ResNet18, RecomputedSegmentsWorkWhenOnlyTheStagesTrain) {
  auto [kept, recomputed] = recompute_pair();
  expect_identical_training(kept, recomputed, Frozen::input_norm_and_stem);
}

// The stem segment with trained parameters but an input that needs no gradient, and the reverse.
TEST(ResNet18, RecomputedStemWorksWithEitherItsInputNormOrItsParametersFrozen) {
  for (const Frozen frozen : {Frozen::input_norm, Frozen::stem}) {
    SCOPED_TRACE(frozen == Frozen::input_norm ? "bn0 frozen" : "stem frozen");
    auto [kept, recomputed] = recompute_pair();
    expect_identical_training(kept, recomputed, frozen);
  }
}

// A segment recomputed in backward runs in bf16 as its forward did: otherwise its gradients would
// be fp32's, and differ.
TEST(ResNet18, RecomputedSegmentsTrainToTheBitLikeKeptActivationsInBf16) {
  auto [kept, recomputed] = recompute_pair(nullptr, Precision::bf16);
  expect_identical_training(kept, recomputed, Frozen::nothing);
}

// Same weights in both precisions: bf16 changes the numbers by its rounding (8 bits of mantissa),
// not more, hands back fp32 embeddings and fp32 gradients, and trains its parameters in fp32.
TEST(ResNet18, Bf16RoundsTheEmbeddingAndKeepsEverythingItHandsBackInFp32) {
  for (const bool training : {true, false}) {
    SCOPED_TRACE(training ? "training" : "inference (folded norms)");
    torch::manual_seed(8);
    ResNet18Options options{3, 16};
    ResNet18Encoder fp32(options);
    options.precision = Precision::bf16;
    ResNet18Encoder bf16(options);
    torch::NoGradGuard no_grad;
    for (auto& item : bf16->named_parameters()) item.value().copy_(fp32->named_parameters()[item.key()]);
    fp32->train(training);
    bf16->train(training);
    torch::manual_seed(9);
    const torch::Tensor batch = torch::randn({6, 3, 16, 20});
    torch::Tensor first_stage;
    const torch::Tensor exact = fp32->forward(batch), rounded = bf16->forward_map(batch, {}, &first_stage);
    const torch::Tensor pooled = torch::adaptive_avg_pool2d(rounded, {1, 1}).flatten(1);
    EXPECT_EQ(rounded.scalar_type(), torch::kFloat);
    EXPECT_EQ(first_stage.scalar_type(), torch::kFloat);
    const double error = ((pooled - exact).norm() / exact.norm()).item<double>();
    EXPECT_GT(error, 1e-4) << "the same numbers as fp32: did bf16 run at all?";
    // Measured here: 0.068 in training (batch statistics of 6 samples on 1 x 2 maps amplify the
    // rounding), under 0.05 at inference.
    EXPECT_LT(error, 0.1);
  }
  torch::manual_seed(8);
  ResNet18Options options{3, 16};
  options.precision = Precision::bf16;
  ResNet18Encoder encoder(options);
  encoder->forward(torch::randn({6, 3, 16, 20})).sum().backward();
  for (const auto& item : encoder->named_parameters()) {
    EXPECT_EQ(item.value().scalar_type(), torch::kFloat) << item.key();
    ASSERT_TRUE(item.value().grad().defined()) << item.key();
    EXPECT_EQ(item.value().grad().scalar_type(), torch::kFloat) << item.key();
  }
  EXPECT_FALSE(at::autocast::is_cpu_enabled()) << "autocast left on after the encoder";
}

TEST(ResNet18, RecomputationIsOnlyForTrainingWithGradients) {
  auto [kept, recomputed] = recompute_pair();
  recomputed->train();
  torch::NoGradGuard no_grad;
  EXPECT_FALSE(graph_has(recomputed->forward(torch::randn({4, 3, 16, 20})).grad_fn(), "RecomputedSegment"));
}

TEST(ResNet18, APassThatWouldExceedTheMemoryBudgetRecomputesToTheBit) {
  const auto budget = std::make_shared<MemoryBudget>(1);
  auto [kept, recomputed] = recompute_pair(budget);
  expect_identical_training(kept, recomputed, Frozen::nothing);
  EXPECT_EQ(budget->take_exceeding_passes(), 3);
  EXPECT_EQ(budget->take_exceeding_passes(), 0);
}

TEST(ResNet18, APassWithinTheMemoryBudgetKeepsItsActivations) {
  const auto budget = std::make_shared<MemoryBudget>(std::int64_t{1} << 50);
  auto [kept, within] = recompute_pair(budget);
  within->train();
  EXPECT_FALSE(graph_has(within->forward(torch::randn({4, 3, 16, 20})).grad_fn(), "RecomputedSegment"));
  EXPECT_EQ(budget->take_exceeding_passes(), 0);
}

// The budget's estimate against what malloc hands out while the stem and the four stages run with
// a graph (LMT108's input, a batch of 8): within 20%.
TEST(ResNet18, PassBytesEstimateWhatTheStemAndStagesKeep) {
  ResNet18Encoder encoder(ResNet18Options{3, 64});
  encoder->train();
  const torch::Tensor normalised = torch::randn({8, 3, 64, 493}, torch::requires_grad());
  const auto run_segments = [&] {
    torch::Tensor out = normalised;
    for (int segment = 0; segment < 5; ++segment) out = encoder->run_segment(segment, out);
    return out;
  };
  // Bytes malloc has handed out, from its heaps and (large blocks) from mmap.
  const auto allocated = [] { return static_cast<std::int64_t>(mallinfo2().uordblks + mallinfo2().hblkhd); };
  run_segments();  // oneDNN's one-time buffers are not activations
  const std::int64_t before = allocated();
  const torch::Tensor out = run_segments();
  const std::int64_t kept = allocated() - before;
  // The estimate also counts the stem map's two gradients, which backward holds beside them.
  const std::int64_t stem_gradients = 2 * 64 * 32 * 247 * 8 * 4;
  const std::int64_t estimate = encoder->training_pass_bytes(normalised) - stem_gradients;
  EXPECT_NEAR(static_cast<double>(kept), static_cast<double>(estimate), 0.2 * static_cast<double>(estimate))
      << "kept " << kept << " bytes, estimated " << estimate;
}

}  // namespace
}  // namespace fscil
