// AMFO's parts against hand-computed values, the encoder's first-stage feature, and a base and
// sessions on a tiny protocol.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/amfo/amfo_head.h"
#include "methods/amfo/amfo_loss.h"
#include "methods/amfo/amfo_method.h"
#include "methods/amfo/fusion_net.h"
#include "methods/common/embedding.h"
#include "methods/common/resnet18.h"
#include "methods/dsn/dsn_head.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

TEST(Cosface, LowersTheTargetCosineByTheMarginInsideTheScale) {
  // cos (0.5, 0.2), label 0, s 32, m 0.1: logits (12.8, 6.4): log(1 + e^-6.4) = 0.00166018.
  const torch::Tensor cosines = torch::tensor({{0.5f, 0.2f}});
  EXPECT_NEAR(cosface_loss(cosines, torch::tensor({0}), 32, 0.1).item<double>(), 0.00166018, 1e-7);
  // Label 1 with the negative margin -0.5: logits (16, 22.4): the same value, an easier target.
  EXPECT_NEAR(cosface_loss(cosines, torch::tensor({1}), 32, -0.5).item<double>(), 0.00166018, 1e-7);
  // Without a margin it is the plain cross-entropy of s x cos: log(1 + e^9.6) for label 1.
  EXPECT_NEAR(cosface_loss(cosines, torch::tensor({1}), 32, 0).item<double>(), 9.600068, 1e-5);
}

// A fusion net over 2 classes whose binary logits are (0, ln 3) for any input: w = (1/4, 3/4).
FusionNet fixed_fusion() {
  FusionNet net(2, 4);
  torch::NoGradGuard no_grad;
  for (auto& parameter : net->parameters()) parameter.zero_();
  net->out->bias[1] = std::log(3.0f);
  return net;
}

TEST(Fusion, MixesThePositiveAndNegativeCosinesByTheNetsSoftmax) {
  FusionNet net = fixed_fusion();
  const torch::Tensor positive = torch::tensor({{0.8f, 0.1f}}), negative = torch::tensor({{0.2f, 0.6f}});
  const Fusion fusion = fuse(*net, positive, negative);
  EXPECT_TRUE(torch::allclose(fusion.mixed, torch::tensor({{0.35f, 0.475f}}), 1e-6)) << fusion.mixed;
  EXPECT_TRUE(torch::allclose(fusion.binary, torch::tensor({{0.0f, std::log(3.0f)}}), 1e-6));
  // The net reads the two softmaxes, the deep head's first: 2C inputs.
  EXPECT_EQ(net->hidden->weight.size(1), 4);
}

TEST(AmfoLoss, BinaryTargetIsNovelFromTheBaseClassesOnAndTheSessionTermsByHand) {
  FusionNet net = fixed_fusion();
  const torch::Tensor positive = torch::tensor({{0.8f, 0.1f}}), negative = torch::tensor({{0.2f, 0.6f}});
  const Fusion fusion = fuse(*net, positive, negative);
  AmfoLossSettings weights;
  weights.binary = 40;
  // 16 b = (0, 16 ln 3): "base" costs log(1 + 3^16) = 17.577796, "novel" log(1 + 3^-16).
  const AmfoLoss as_base = amfo_loss(positive, negative, fusion, torch::tensor({1}), 2, weights);
  EXPECT_NEAR(as_base.binary.item<double>(), 40 * 17.577796, 1e-3);
  const AmfoLoss as_novel = amfo_loss(positive, negative, fusion, torch::tensor({1}), 1, weights);
  EXPECT_NEAR(as_novel.binary.item<double>(), 40 * 2.3230573e-8, 1e-6);  // below float32's resolution of 1 + x
  // The fused CE: 16 x (0.35, 0.475) for label 1: log(1 + e^-2) = 0.126928.
  EXPECT_NEAR(as_base.fusion.item<double>(), 0.126928, 1e-5);
  EXPECT_EQ(as_base.sparsity.item<double>(), 0.0);
  EXPECT_EQ(as_base.distillation.item<double>(), 0.0);

  AmfoLoss session = as_base;
  // Gate (0.2, 0.4): 0.1 x mean, counted for alpha and alpha_n: 0.06.
  add_session_terms(session, positive, positive.detach(), 16, torch::tensor({0.2f, 0.4f}), 0);
  EXPECT_NEAR(session.sparsity.item<double>(), 0.06, 1e-7);
  // Distillation: teacher softmax(16 x (0.8, 0.1) / 0.5) = (1 - e^-22.4, e^-22.4); student
  // log_softmax((0.8, 0.1) / 0.5) = (-log(1 + e^-1.4), -1.4 - log(1 + e^-1.4)).
  const double student_first = -std::log1p(std::exp(-1.4)), teacher_second = std::exp(-22.4);
  EXPECT_NEAR(session.distillation.item<double>(),
              -((1 - teacher_second) * student_first + teacher_second * (-1.4 + student_first)), 1e-6);
  // Nothing when the mean gate is below r = 0.5.
  add_session_terms(session, positive, positive.detach(), 16, torch::tensor({0.2f, 0.4f}), 0.5);
  EXPECT_EQ(session.sparsity.item<double>(), 0.0);
}

TEST(AmfoCosines, TheNegativeBaseHeadReadsTheFirstStageOnlyBeforeTheFirstSession) {
  torch::manual_seed(3);
  AmfoHead head(4, 2, 4, 3);
  SessionSupports supports;
  NegativeHeads negative_heads;
  const torch::Tensor x = torch::randn({5, 4}), first_stage = torch::randn({5, 2});
  const HeadCosines before = amfo_cosines(*head, *supports, *negative_heads, x, first_stage, 0.2);
  const torch::Tensor u = torch::nn::functional::linear(x, head->fc1->weight);
  const torch::Tensor shallow = torch::nn::functional::linear(head->shallow->forward(first_stage), head->fc1->weight);
  EXPECT_TRUE(torch::allclose(before.positive, row_cosines(u, head->positive->weight), 1e-6));
  EXPECT_TRUE(torch::allclose(before.negative, row_cosines(shallow, head->negative->weight), 1e-6));
  // A session: both base heads read u; the session's columns score the gated node by each head.
  const torch::Tensor rows = torch::randn({2, 4}), negative_rows = torch::randn({2, 4});
  supports->add_session(torch::eye(4), rows);
  negative_heads->add_session(negative_rows);
  const torch::Tensor gate = torch::full({4}, 0.5f);
  const HeadCosines after = amfo_cosines(*head, *supports, *negative_heads, x, first_stage, 0.2, gate);
  const torch::Tensor node = dsn_l2_norm(0.2 * u + 0.5 * row_cosines(x, torch::eye(4)));
  EXPECT_TRUE(torch::allclose(after.negative.slice(1, 0, 3), row_cosines(u, head->negative->weight), 1e-6));
  EXPECT_TRUE(torch::allclose(after.positive.slice(1, 3), row_cosines(node, rows), 1e-5));
  EXPECT_TRUE(torch::allclose(after.negative.slice(1, 3), row_cosines(node, negative_rows), 1e-5));
}

TEST(ResNet18Encoder, TheFirstStageFeatureBesideTheSameEmbedding) {
  torch::manual_seed(4);
  ResNet18Options options;
  options.mel_bins = 8;
  ResNet18Encoder folded(options);
  options.fold_norms_at_inference = false;
  torch::manual_seed(4);
  ResNet18Encoder unfolded(options);
  const torch::Tensor x = torch::randn({3, 1, 8, 12});
  torch::NoGradGuard no_grad;
  folded->eval();
  unfolded->eval();
  const auto [embedding, first_stage] = folded->forward_with_first_stage(x);
  EXPECT_TRUE(torch::equal(embedding, folded->forward(x)));
  EXPECT_EQ(first_stage.sizes(), (std::vector<std::int64_t>{3, 64}));
  // The folded inference path keeps the same stage output as the segment-by-segment one.
  const auto [unfolded_embedding, unfolded_first_stage] = unfolded->forward_with_first_stage(x);
  EXPECT_TRUE(torch::allclose(first_stage, unfolded_first_stage, 1e-4, 1e-5));
  EXPECT_TRUE(torch::allclose(embedding, unfolded_embedding, 1e-4, 1e-5));
  EXPECT_TRUE(torch::equal(unfolded_embedding, unfolded->forward(x)));
  EXPECT_GT(first_stage.abs().sum().item<double>(), 0.0);
}

ParameterSet tiny_amfo_params(int session_epochs) {
  ParameterSet params;
  params.set("pretrain_epochs", "2");
  params.set("batch_size", "32");
  params.set("amfo_session_epochs", std::to_string(session_epochs));
  return params;
}

TEST(AmfoMethod, BaseTrainsEveryPartAndASessionOnlyItsBranchHeadsAndFusionNet) {
  torch::manual_seed(5);
  AmfoMethod untrained([] {
    ParameterSet params = tiny_amfo_params(3);
    params.set("pretrain_epochs", "0");
    return params;
  }());
  RunContext untrained_context = tiny_context(5);
  untrained.train_base(tiny_base(), untrained_context);
  torch::manual_seed(5);
  AmfoMethod method(tiny_amfo_params(3));
  RunContext context = tiny_context(5);
  const SessionData base_data = tiny_base();
  method.train_base(base_data, context);
  const MethodState before = untrained.save_state(), base = method.save_state();
  for (const std::string name : {"encoder.conv1.weight", "head.shallow.weight", "head.fc1.weight", "head.positive.weight",
                                 "head.negative.weight", "fusion.net.hidden.weight", "fusion.net.out.bias"}) {
    ASSERT_EQ(base.count(name), 1u) << name;
    EXPECT_FALSE(torch::equal(before.at(name), base.at(name))) << name << " did not train";
  }
  // embed(): the embedding, then the pooled first stage; the Gaussians are of the embedding.
  const torch::Tensor embedded = method.embed_rows(base_data.features);
  ASSERT_EQ(embedded.size(1), 256 + 64);
  const torch::Tensor class_three =
      embedded.slice(1, 0, 256).index_select(0, torch::nonzero(base_data.labels == 3).view(-1));
  EXPECT_TRUE(torch::allclose(base.at("gaussians.means")[3], class_three.mean(0), 1e-5, 1e-6));
  EXPECT_EQ(base.at("fusion.net.hidden.weight").size(1), 2 * 6);

  const SessionData support = tiny_support(6);
  method.learn_session(support, context);
  const MethodState first = method.save_state();
  ASSERT_EQ(context.training_log.size(), 2u + 3u);  // two base epochs, three session epochs
  // Both of the session's heads started at l2n(fc1 x the shots' mean); they were trained apart
  // (different margins), the branch moved from fc1, the fusion net is a new one over 8 classes.
  EXPECT_FALSE(torch::allclose(first.at("supports.head1"), first.at("negative_heads.head1")));
  EXPECT_FALSE(torch::allclose(first.at("supports.branch1"), base.at("head.fc1.weight")));
  EXPECT_EQ(first.at("fusion.net.hidden.weight").size(1), 2 * 8);
  for (const auto& [name, tensor] : base) {
    if (name.rfind("gaussians.", 0) == 0 || name.rfind("fusion.", 0) == 0 || name == "seen_classes.count") continue;
    EXPECT_TRUE(torch::equal(first.at(name), tensor)) << name << " changed in session 1";
  }
  EXPECT_TRUE(torch::equal(first.at("gaussians.covariances").slice(0, 0, 6), base.at("gaussians.covariances").slice(0, 0, 6)));
  const torch::Tensor embeddings = method.embed_rows(support.features);
  const torch::Tensor logits = method.classify(embeddings);
  EXPECT_EQ(logits.sizes(), (std::vector<std::int64_t>{10, 8}));
  // The session's losses are logged in their parts, the distillation without effect but counted.
  const auto& last = context.training_log.back().values;
  for (const char* part : {"margin", "fusion", "binary", "kd", "sparsity", "gate_mean"}) EXPECT_EQ(last.count(part), 1u) << part;
}

TEST(AmfoMethod, TheSessionsFusionNetIsANewOneAndTrains) {
  // The same seed with no session epochs: the fusion net as the session creates it.
  const auto fusion_after_session = [](int session_epochs) {
    torch::manual_seed(9);
    AmfoMethod method(tiny_amfo_params(session_epochs));
    RunContext context = tiny_context(9);
    method.train_base(tiny_base(), context);
    const MethodState base = method.save_state();
    method.learn_session(tiny_support(6), context);
    return std::pair{base, method.save_state()};
  };
  const auto [base, fresh] = fusion_after_session(0);
  const auto [same_base, trained] = fusion_after_session(2);
  EXPECT_TRUE(torch::equal(base.at("head.fc1.weight"), same_base.at("head.fc1.weight")));
  EXPECT_FALSE(torch::equal(fresh.at("fusion.net.hidden.weight").slice(1, 0, 6), base.at("fusion.net.hidden.weight").slice(1, 0, 6)));
  for (const std::string name : {"fusion.net.hidden.weight", "fusion.net.out.weight", "negative_heads.head1", "supports.head1"}) {
    EXPECT_FALSE(torch::equal(fresh.at(name), trained.at(name))) << name << " did not train";
  }
}

}  // namespace
}  // namespace fscil
