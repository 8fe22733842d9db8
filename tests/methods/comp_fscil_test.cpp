// Comp-FSCIL's heads against hand-computed values, the shared encoder's map, and a session's
// effect on a tiny protocol.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/common/embedding.h"
#include "methods/comp_fscil/comp_fscil_method.h"
#include "methods/comp_fscil/compositional_heads.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

// One position per set: D x 1 maps.
torch::Tensor column(std::initializer_list<float> values) {
  return torch::tensor(std::vector<float>(values)).view({1, -1, 1});
}

TEST(CompositionalHeads, SignedPowerKeepsTheNegativePartAndHasNoGradientAtZero) {
  const torch::Tensor x = torch::tensor({4.0f, 0.0f, -2.0f, 1.0f}, torch::requires_grad());
  const torch::Tensor y = signed_power(x, 0.5);
  EXPECT_TRUE(torch::allclose(y, torch::tensor({2.0f, 0.0f, -2.0f, 1.0f})));
  y.sum().backward();
  EXPECT_TRUE(torch::allclose(x.grad(), torch::tensor({0.25f, 0.0f, 1.0f, 0.5f}))) << x.grad();
  EXPECT_NEAR(signed_power(torch::tensor({2.0f}), 1.2).item<double>(), 2.297397, 1e-5);
}

TEST(CompositionalHeads, CkaOfOnePositionIsTheSquaredCentredCosine) {
  // (1, 2, 3) -> (-1, 0, 1); (3, 1, 2) -> (1, -1, 0): cos -0.5, CKA 0.25, whatever the sign.
  const torch::Tensor a = column({1, 2, 3});
  EXPECT_NEAR(cka_similarity(a, column({3, 1, 2})).item<double>(), 0.25, 1e-6);
  EXPECT_NEAR(cka_similarity(a, column({-3, -1, -2})).item<double>(), 0.25, 1e-6);
}

TEST(CompositionalHeads, CkaComparesSetsOfPrimitives) {
  // Centred columns a1 (1, 0, -1), a2 (0, 1, -1); p1 (1, 0, -1), p2 (1, -1, 0): ||A^T P||^2 = 7,
  // ||A^T A|| = ||P^T P|| = sqrt 10, so 0.7; the order of the primitives and the scale do not count.
  const torch::Tensor map = torch::tensor({{6.0f, 2.0f}, {5.0f, 3.0f}, {4.0f, 1.0f}}).view({1, 3, 2, 1});
  const torch::Tensor prototype = torch::tensor({{3.0f, 4.0f}, {2.0f, 2.0f}, {1.0f, 3.0f}}).view({1, 3, 2, 1});
  EXPECT_NEAR(cka_similarity(map, prototype).item<double>(), 0.7, 1e-6);
  EXPECT_NEAR(cka_similarity(map, prototype.flip(2)).item<double>(), 0.7, 1e-6);
  EXPECT_NEAR(cka_similarity(3 * map, prototype).item<double>(), 0.7, 1e-6);
  EXPECT_NEAR(cka_similarity(map, map).item<double>(), 1.0, 1e-6);
  // A map constant over channels scores 0, not NaN.
  EXPECT_EQ(cka_similarity(torch::ones({1, 3, 2, 1}), prototype).item<double>(), 0.0);
}

TEST(CompositionalHeads, OnlyTheSampleIsPowered) {
  // (4, 1, 0)^0.5 = (2, 1, 0), the prototype itself: CKA 1; unpowered 0.923077.
  const torch::Tensor sample = column({4, 1, 0}), prototype = column({2, 1, 0});
  EXPECT_NEAR(cka_similarity(signed_power(sample, 0.5), prototype).item<double>(), 1.0, 1e-6);
  EXPECT_NEAR(cka_similarity(sample, prototype).item<double>(), 0.923077, 1e-6);
}

TEST(CompositionalHeads, VectorHeadTrainsOnDistancesAndTestsOnCosines) {
  // Centred, (-1, 0, 1) and (1, -1, 0): -6 (uncentred it would be -9) and cos -0.5.
  const torch::Tensor x = torch::tensor({{1.0f, 2.0f, 3.0f}}), w = torch::tensor({{4.0f, 2.0f, 3.0f}});
  EXPECT_NEAR(vector_distance_logits(x, w, 1).item<double>(), -6.0, 1e-5);
  EXPECT_NEAR(vector_cosine_logits(x, w, 1).item<double>(), -0.5, 1e-6);
  EXPECT_NEAR(vector_distance_logits(x, w, 2).item<double>(), -12.0, 1e-5);
}

TEST(CompositionalHeads, ReuseRebuildsEachClassFromTheOthersPrimitives) {
  // Centred base primitives q0 (1, 0, -1), q1 (1, -1, 0), q2 (0, 1, -1); tau 1. R0 = (q1 + q2)/2,
  // R1 = 0.982014 q0 + 0.017986 q2, R2 = 0.982014 q0 + 0.017986 q1; the sample (2, 1, 0) -> q0.
  const torch::Tensor prototypes = torch::cat({column({2, 1, 0}), column({3, 1, 2}), column({1, 2, 0})});
  const torch::Tensor similarity = reuse_similarity(column({2, 1, 0}), prototypes, 1.0);
  EXPECT_TRUE(torch::allclose(similarity, torch::tensor({{0.999999f, 0.999753f, 0.999753f}}), 1e-5, 1e-6)) << similarity;
  const torch::Tensor logits = 16 * similarity;
  EXPECT_NEAR(torch::nn::functional::cross_entropy(logits, torch::tensor({0})).item<double>(), 1.095987, 1e-4);
  // The weights are detached and the own class masked: R1 does not depend on q1.
  const torch::Tensor trainable = prototypes.clone().requires_grad_(true);
  reuse_similarity(column({2, 1, 0}), trainable, 1.0).select(1, 1).sum().backward();
  EXPECT_EQ(trainable.grad()[1].abs().sum().item<double>(), 0.0);
  EXPECT_GT(trainable.grad()[0].abs().sum().item<double>(), 0.0);
}

ParameterSet tiny_comp_params() {
  ParameterSet params;
  params.set("pretrain_epochs", "1");
  params.set("batch_size", "32");
  params.set("comp_session_steps", "5");
  return params;
}

TEST(CompFscilMethod, EmbedsTheMapWhoseMeanIsTheEncodersEmbedding) {
  torch::manual_seed(3);
  RunContext context = tiny_context(3);
  ResNet18Encoder encoder(encoder_options(context));
  const torch::Tensor features = torch::randn({3, 2, 4, 4});
  const torch::Tensor maps = embed_maps_in_batches(encoder, features);
  EXPECT_TRUE(torch::allclose(maps.mean({2, 3}), embed_in_batches(encoder, features), 1e-5, 1e-6));
}

TEST(CompFscilMethod, ASessionStartsAtTheShotMeansAndTrainsOnlyItsRowsAndMaps) {
  torch::manual_seed(5);
  CompFscilMethod method(tiny_comp_params());
  RunContext context = tiny_context(5);
  method.train_base(tiny_base(), context);
  const MethodState base = method.save_state();
  const SessionData support = tiny_support(6);
  ParameterSet no_steps = tiny_comp_params();
  no_steps.set("comp_session_steps", "0");
  CompFscilMethod untrained(no_steps);
  untrained.restore_state(base, context);
  untrained.learn_session(support, context);
  const torch::Tensor maps = method.embed_rows(support.features).view({10, 256, -1});
  const MethodState started = untrained.save_state();
  EXPECT_TRUE(torch::allclose(started.at("novel_prototypes.rows").slice(0, 0, 2),
                              class_means(maps.mean(2), support.labels, {6, 7}), 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(started.at("novel_prototypes.maps").slice(0, 0, 2).flatten(1),
                              class_means(maps.flatten(1), support.labels, {6, 7}), 1e-5, 1e-6));
  method.learn_session(support, context);
  const MethodState after = method.save_state();
  for (const auto& [name, tensor] : base) {
    if (name.rfind("novel_prototypes.", 0) == 0 || name == "seen_classes.count") continue;
    EXPECT_TRUE(torch::equal(after.at(name), tensor)) << name << " changed in a session";
  }
  EXPECT_FALSE(torch::allclose(after.at("novel_prototypes.rows").slice(0, 0, 2),
                               started.at("novel_prototypes.rows").slice(0, 0, 2)));
  // CKA ignores a prototype's scale, so its gradient shrinks as the map grows (here the tiny base's
  // maps reach 1e6): the maps move, if little.
  EXPECT_FALSE(torch::equal(after.at("novel_prototypes.maps").slice(0, 0, 2),
                            started.at("novel_prototypes.maps").slice(0, 0, 2)));
  EXPECT_TRUE(torch::equal(after.at("novel_prototypes.rows").slice(0, 2), base.at("novel_prototypes.rows").slice(0, 2)));
  EXPECT_EQ(method.classify(method.embed_rows(support.features)).sizes(), (std::vector<std::int64_t>{10, 8}));
}

}  // namespace
}  // namespace fscil
