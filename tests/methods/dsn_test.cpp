// DSN's parts against hand-computed values, and a session's effect on a tiny protocol.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "methods/common/class_statistics.h"
#include "methods/common/embedding.h"
#include "methods/dsn/class_gaussians.h"
#include "methods/dsn/dsn_head.h"
#include "methods/dsn/dsn_method.h"
#include "methods/dsn/session_loss.h"
#include "methods/dsn/session_supports.h"
#include "methods/dsn/shot_confusion.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

// D = N = 2, fc1 = base rows = I, one session whose branch is I and whose head row is (1, 1)/sqrt 2.
struct TwoDimensionalNet {
  DsnHead head{2, 2, 2};
  SessionSupports supports;
  TwoDimensionalNet() {
    torch::NoGradGuard no_grad;
    head->fc1->weight.copy_(torch::eye(2));
    head->base->weight.copy_(torch::eye(2));
    supports->add_session(torch::eye(2), torch::tensor({{1.0f, 1.0f}}) / std::sqrt(2.0f));
  }
};

TEST(DsnGate, SigmoidOfTheBatchMeanSharpenedByTheEpoch) {
  const torch::Tensor a = torch::tensor({{0.5f, -0.5f}, {0.3f, -0.1f}});
  const torch::Tensor first = training_gate(a, 0), fifth = training_gate(a, 4);
  EXPECT_TRUE(torch::allclose(first, torch::tensor({0.598688f, 0.425557f}), 1e-5, 1e-6)) << first;
  EXPECT_TRUE(torch::allclose(fifth, torch::tensor({0.880797f, 0.182426f}), 1e-5, 1e-6)) << fifth;
  // The compression term is 0.1 x the mean gate.
  const torch::Tensor logits = torch::zeros({1, 2}), labels = torch::zeros({1}, torch::kLong);
  EXPECT_NEAR(dsn_session_loss(logits, labels, logits, first, 16).compression.item<double>(), 0.0512123, 1e-6);
  EXPECT_NEAR(dsn_session_loss(logits, labels, logits, fifth, 16).compression.item<double>(), 0.0531611, 1e-6);
}

TEST(DsnForward, TheSessionScoresThroughItsGatedSupport) {
  // u = (0.6, 0.8); a = cos(x, I) = u; gate (1, 0): v = l2n(0.2 u + (0.6, 0)) = (0.976186, 0.216930).
  TwoDimensionalNet net;
  net.supports->gate(1).copy_(torch::tensor({1.0f, 0.0f}));
  const torch::Tensor logits = dsn_cosines(*net.head, *net.supports, torch::tensor({{3.0f, 4.0f}}), 0.2, 1);
  EXPECT_TRUE(torch::allclose(logits, torch::tensor({{0.6f, 0.8f, 0.843661f}}), 1e-4, 1e-5)) << logits;
  // Without the session, the base cosines alone.
  EXPECT_EQ(dsn_cosines(*net.head, *net.supports, torch::tensor({{3.0f, 4.0f}}), 0.2, 0).size(1), 2);
}

TEST(DsnSessionLoss, CrossEntropyDistillationAndCompressionByHand) {
  // An old row (3, 4) of class 0 with the stored gate 0, a new row (1, 2) of class 2 with the
  // training gate of epoch 0; the teacher is the base network, whose logits are the first columns.
  TwoDimensionalNet net;
  const torch::Tensor new_row = torch::tensor({{1.0f, 2.0f}});
  const torch::Tensor gate = training_gate(net.supports->branch_cosines(1, new_row), 0);
  EXPECT_TRUE(torch::allclose(gate, torch::tensor({0.609977f, 0.709803f}), 1e-5, 1e-6)) << gate;
  const torch::Tensor old_output = dsn_cosines(*net.head, *net.supports, torch::tensor({{3.0f, 4.0f}}), 0.2, 1);
  const torch::Tensor new_output = dsn_cosines(*net.head, *net.supports, new_row, 0.2, 1, gate);
  EXPECT_TRUE(torch::allclose(old_output, torch::tensor({{0.6f, 0.8f, 0.989949f}}), 1e-4, 1e-5)) << old_output;
  EXPECT_TRUE(torch::allclose(new_output, torch::tensor({{0.447214f, 0.894427f, 0.933553f}}), 1e-4, 1e-5)) << new_output;
  const torch::Tensor output = torch::cat({old_output, new_output});
  const DsnSessionLoss loss = dsn_session_loss(output, torch::tensor({0, 2}), output.slice(1, 0, 2), gate, 16);
  EXPECT_NEAR(loss.cross_entropy.item<double>(), 3.358216, 1e-4);
  EXPECT_NEAR(loss.distillation.item<double>(), 0.006143, 1e-4);
  EXPECT_NEAR(loss.compression.item<double>(), 0.0659890, 1e-5);
  EXPECT_NEAR(loss.total().item<double>(), 3.430348, 1e-4);
  // A batch without new rows has no compression term.
  EXPECT_EQ(dsn_session_loss(old_output, torch::tensor({0}), old_output.slice(1, 0, 2), {}, 16).compression.item<double>(), 0);
}

TEST(ClassGaussians, CovarianceDividesByNMinusOneAndBlendsAtFourFifths) {
  const torch::Tensor shots = torch::tensor({{1.0f, 0.0f}, {-1.0f, 0.0f}, {0.0f, 2.0f}, {0.0f, -2.0f}, {0.0f, 0.0f}});
  const torch::Tensor covariance = sample_covariance(shots);
  EXPECT_TRUE(torch::allclose(covariance, torch::tensor({{0.5f, 0.0f}, {0.0f, 2.0f}}))) << covariance;
  EXPECT_TRUE(torch::equal(sample_covariance(shots.slice(0, 0, 1)), torch::zeros({2, 2})));
  ClassGaussians gaussians(3, 2);
  gaussians->insert(1, torch::tensor({{1.0f, 2.0f}}), covariance.unsqueeze(0));
  EXPECT_TRUE(torch::equal(gaussians->means()[1], torch::tensor({1.0f, 2.0f})));  // the first insert copies
  gaussians->blend(1, torch::tensor({{6.0f, -3.0f}}), torch::eye(2).unsqueeze(0));
  EXPECT_TRUE(torch::allclose(gaussians->means()[1], torch::tensor({2.0f, 1.0f})));
  EXPECT_TRUE(torch::allclose(gaussians->covariances()[1], torch::tensor({{0.6f, 0.0f}, {0.0f, 1.8f}})));
}

TEST(ClassGaussians, DrawsFollowTheCovarianceEvenWhenItIsSingular) {
  const torch::Tensor covariance = torch::tensor({{4.0, 1.0}, {1.0, 3.0}}, torch::kDouble);
  const torch::Tensor factor = gaussian_factor(covariance);
  EXPECT_TRUE(torch::allclose(factor.matmul(factor.t()), covariance, 1e-9, 1e-9));
  // Rank one, with a rounding-negative eigenvalue: every draw lies on the line x1 - x2 = 1.
  const torch::Tensor singular = torch::tensor({{1.0, 1.0}, {1.0, 1.0 - 1e-9}}, torch::kDouble);
  EXPECT_FALSE(gaussian_factor(singular).isnan().any().item<bool>());
  torch::manual_seed(3);
  ClassGaussians gaussians(2, 2);
  gaussians->insert(0, torch::tensor({{1.0f, 0.0f}, {0.0f, 0.0f}}),
                    torch::stack({torch::ones({2, 2}), torch::diag(torch::tensor({4.0f, 1.0f}))}));
  const GaussianDraws line = gaussians->draw(1, 1, 0, DrawCounts{50, 4, 4, 4});
  EXPECT_TRUE(torch::allclose(line.features.select(1, 0) - line.features.select(1, 1), torch::ones({50}), 1e-4, 1e-5));
  const GaussianDraws many = gaussians->draw(2, 2, 1, DrawCounts{200000, 4, 4, 4});
  const torch::Tensor second = many.features.slice(0, 4);  // class 0 first: its 4 regular draws
  ASSERT_EQ(second.size(0), 200000);
  const torch::Tensor spread = sample_covariance(second.to(torch::kDouble));
  EXPECT_NEAR(spread[0][0].item<double>(), 4.0, 0.08);
  EXPECT_NEAR(spread[1][1].item<double>(), 1.0, 0.02);
  EXPECT_NEAR(spread[0][1].item<double>(), 0.0, 0.02);
}

TEST(ClassGaussians, OldClassesDrawTheirRegularCountPlusWhatConfusionEarnedUpToTheCap) {
  torch::manual_seed(4);
  ClassGaussians gaussians(4, 2);
  gaussians->insert(0, torch::zeros({4, 2}), torch::eye(2).expand({4, 2, 2}).contiguous());
  const DrawCounts counts{2, 5, 4, 4};  // current 2; base cap 5, earlier novel cap 4; regular 4
  const auto per_class = [](const GaussianDraws& draws) {
    return torch::bincount(draws.labels, {}, 4);
  };
  // Classes 0-1 base, 2 an earlier session's, 3 the current session's.
  GaussianDraws draws = gaussians->draw(4, 2, 3, counts);
  EXPECT_TRUE(torch::equal(per_class(draws), torch::tensor({4, 4, 4, 2})));
  for (int i = 0; i < 2; ++i) gaussians->add_draw(0), gaussians->add_draw(2);
  gaussians->add_draw(1);
  draws = gaussians->draw(4, 2, 3, counts);
  EXPECT_TRUE(torch::equal(per_class(draws), torch::tensor({5, 5, 4, 2})));  // capped at 5 and 4
  draws = gaussians->draw(4, 2, 3, counts);
  EXPECT_TRUE(torch::equal(per_class(draws), torch::tensor({4, 4, 4, 2})));  // spent
}

TEST(ShotConfusion, CalibratesWithNearUniformWeightsAndCompounds) {
  // Base covariances I and 2I, own 0.5 I, every cosine 0: weights 1/3 each.
  ShotConfusion confusion(2, 2, 1);
  confusion.record(torch::zeros({2, 3}), torch::tensor({2, 2}));
  const torch::Tensor weights = confusion.base_weights(0);
  EXPECT_TRUE(torch::allclose(weights, torch::full({3}, 1.0f / 3)));
  const torch::Tensor bases = torch::stack({torch::eye(2), 2 * torch::eye(2)});
  const torch::Tensor once = calibrated_covariance(0.5 * torch::eye(2), weights, bases);
  EXPECT_TRUE(torch::allclose(once, 1.166667 * torch::eye(2), 1e-5, 1e-6)) << once;
  EXPECT_TRUE(torch::allclose(calibrated_covariance(once, weights, bases), 1.388889 * torch::eye(2), 1e-5, 1e-6));
  EXPECT_THROW(ShotConfusion(2, 2, 2).base_weights(1), MethodError);
}

TEST(ShotConfusion, OldClassesAmongTheTopKThatReachTheOwnWeightEarnADraw) {
  const torch::Tensor weights = torch::tensor({0.5f, 0.2f, 0.3f});  // old 0, old 1 | own
  EXPECT_EQ(confused_old_classes(weights, 1), (std::vector<std::int64_t>{0}));
  EXPECT_EQ(confused_old_classes(weights, 2), (std::vector<std::int64_t>{0}));
  EXPECT_EQ(confused_old_classes(torch::tensor({0.5f, 0.3f, 0.2f}), 2), (std::vector<std::int64_t>{0, 1}));
}

ParameterSet tiny_dsn_params(int session_epochs) {
  ParameterSet params;
  params.set("pretrain_epochs", "1");
  params.set("batch_size", "32");
  params.set("dsn_session_epochs", std::to_string(session_epochs));
  return params;
}

TEST(DsnMethod, BaseKeepsEachClassGaussianAndASessionStartsFromFc1AndTheShotMeans) {
  torch::manual_seed(5);
  DsnMethod method(tiny_dsn_params(0));
  RunContext context = tiny_context(5);
  const SessionData base_data = tiny_base();
  method.train_base(base_data, context);
  const torch::Tensor embeddings = method.embed_rows(base_data.features);
  const MethodState base = method.save_state();
  EXPECT_TRUE(torch::allclose(base.at("gaussians.means").slice(0, 0, 6),
                              class_means(embeddings, base_data.labels, {0, 1, 2, 3, 4, 5}), 1e-5, 1e-6));
  const torch::Tensor class_two = embeddings.index_select(0, torch::nonzero(base_data.labels == 2).view(-1));
  EXPECT_TRUE(torch::allclose(base.at("gaussians.covariances")[2], sample_covariance(class_two), 1e-4, 1e-6));
  const SessionData support = tiny_support(6);
  method.learn_session(support, context);
  const MethodState after = method.save_state();
  EXPECT_TRUE(torch::equal(after.at("supports.branch1"), base.at("head.fc1.weight")));
  const torch::Tensor means = class_means(method.embed_rows(support.features), support.labels, {6, 7});
  const torch::Tensor projected = torch::nn::functional::linear(means, base.at("head.fc1.weight"));
  EXPECT_TRUE(torch::allclose(after.at("supports.head1"), projected / (projected.norm(2, 1, true) + 1e-6), 1e-5, 1e-6));
  EXPECT_TRUE(torch::equal(after.at("supports.gate1"), torch::zeros({256})));
  EXPECT_TRUE(torch::allclose(after.at("gaussians.means").slice(0, 6, 8), means, 1e-5, 1e-6));
}

TEST(DsnMethod, ASessionTrainsOnlyItsBranchHeadAndGate) {
  torch::manual_seed(6);
  DsnMethod method(tiny_dsn_params(4));
  RunContext context = tiny_context(6);
  method.train_base(tiny_base(), context);
  const MethodState base = method.save_state();
  method.learn_session(tiny_support(6), context);
  const MethodState first = method.save_state();
  ASSERT_EQ(context.training_log.size(), 1u + 4u);  // one base epoch, four session epochs
  // The branch and the head moved from where they started (fc1 and the projected shot means);
  // the encoder, fc1 and the base rows did not.
  EXPECT_FALSE(torch::allclose(first.at("supports.branch1"), base.at("head.fc1.weight")));
  for (const auto& [name, tensor] : base) {
    if (name.rfind("gaussians.", 0) == 0 || name == "seen_classes.count") continue;
    EXPECT_TRUE(torch::equal(first.at(name), tensor)) << name << " changed in session 1";
  }
  method.learn_session(tiny_support(8), context);
  const MethodState second = method.save_state();
  for (const auto& [name, tensor] : first) {
    if (name.rfind("gaussians.", 0) == 0 || name == "seen_classes.count") continue;
    EXPECT_TRUE(torch::equal(second.at(name), tensor)) << name << " changed in session 2";
  }
  EXPECT_TRUE(torch::equal(second.at("gaussians.covariances").slice(0, 0, 8),
                           first.at("gaussians.covariances").slice(0, 0, 8)));
  EXPECT_EQ(method.classify(torch::randn({3, 256})).sizes(), (std::vector<std::int64_t>{3, 10}));
  // Cost: fc1 and two branches (256 x 256 each), the cosines of 6 + 2 + 2 rows; trained in sessions:
  // the two branches and heads.
  const ModelCost cost = method.inference_cost(InputShape{2, 4, 4});
  EXPECT_EQ(cost.trainable_parameters(), 2 * (256 * 256 + 2 * 256));
}

TEST(DsnMethod, TestOracleKeepsTheSessionEpochThatScoredBest) {
  torch::manual_seed(7);
  DsnMethod method(tiny_dsn_params(6));
  RunContext context = tiny_context(7);
  method.train_base(tiny_base(), context);
  // The shots stand in for the test samples the release scores each epoch on.
  const SessionData support = tiny_support(6);
  context.selection = EpochSelection::test_oracle;
  context.oracle_test = &support;
  context.training_log.clear();
  method.learn_session(support, context);
  std::vector<double> scores;
  for (const EpochLog& epoch : context.training_log) scores.push_back(epoch.values.at("selection_score"));
  ASSERT_EQ(scores.size(), 6u);
  const double best = *std::max_element(scores.begin(), scores.end());
  ASSERT_NE(best, *std::min_element(scores.begin(), scores.end())) << "the epochs must score differently";
  EXPECT_EQ(context.diagnostics.at("session_selection_score"), best);
  EXPECT_NEAR(method.accuracy_on(support), best, 1e-9);
  const int kept = static_cast<int>(context.diagnostics.at("session_kept_epoch"));
  EXPECT_EQ(scores[kept - 1], best);
  for (std::size_t e = kept; e < scores.size(); ++e) EXPECT_LT(scores[e], best);  // ties go to the later epoch
}

}  // namespace
}  // namespace fscil
