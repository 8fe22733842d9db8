// ADBS's parts against hand-computed values, and the method's session update on a tiny protocol.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/adbs/adbs_method.h"
#include "methods/adbs/decision_boundaries.h"
#include "methods/common/embedding.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

TEST(InterClassConstraint, IsTheMeanOfThePositivePartOverEveryOrderedPair) {
  // w_1 = (1, 0), w_2 = (0.6, 0.8) given at length 2: w_1.w_2 = 0.6 once normalised.
  // D_12 = (1 - 0.6) - (m_2 - m_1 0.6) = 0.4 - (0.5 - 0.6) = 0.5
  // D_21 = (1 - 0.6) - (m_1 - m_2 0.6) = 0.4 - (1 - 0.3) = -0.3; the diagonal is 0.
  const torch::Tensor rows = torch::tensor({{1.0f, 0.0f}, {1.2f, 1.6f}});
  const torch::Tensor margins = torch::tensor({1.0f, 0.5f});
  EXPECT_NEAR(inter_class_constraint(margins, rows).item<double>(), 0.5 / 4, 1e-6);
  // Wide margins for both: every D_ij <= 0, nothing to pay.
  EXPECT_NEAR(inter_class_constraint(torch::tensor({2.0f, 2.0f}), rows).item<double>(), 0.0, 1e-7);
}

TEST(InterClassConstraint, PushesTheSmallerMarginUp) {
  const torch::Tensor rows = torch::tensor({{1.0f, 0.0f}, {0.6f, 0.8f}});
  const torch::Tensor margins = torch::tensor({1.0f, 0.5f}, torch::requires_grad());
  inter_class_constraint(margins, rows).backward();
  // Only D_12 = 0.4 - m_2 + 0.6 m_1 is active: d/dm_1 = 0.6 / 4, d/dm_2 = -1 / 4.
  EXPECT_NEAR(margins.grad()[0].item<double>(), 0.15, 1e-6);
  EXPECT_NEAR(margins.grad()[1].item<double>(), -0.25, 1e-6);
}

TEST(TrainNewMargins, TakesDampedMomentumStepsOnTheNewMarginsOnly) {
  // One shot of the new class 1, both cosine logits 8; old margin 1.2, the new one starts there.
  // Step 1: p = (0.5, 0.5), dCE/dm_1 = (0.5 - 1) x 8 = -4 -> m_1 = 1.2 + 0.1 x 4 = 1.6.
  // Step 2: logits (9.6, 12.8), p_1 = 1 / (1 + e^-3.2), dCE/dm_1 = (p_1 - 1) x 8; the momentum
  // buffer is 0.9 x -4 + (1 - 0.9) x that gradient (dampening 0.9).
  // The rows are orthogonal, so D_01 = 1 - m_1 and D_10 = 1 - m_0 stay negative: no IC gradient.
  const torch::Tensor logits = torch::tensor({{8.0f, 8.0f}});
  const torch::Tensor labels = torch::tensor({1}, torch::kLong);
  const torch::Tensor rows = torch::tensor({{1.0f, 0.0f}, {0.0f, 1.0f}});
  const torch::Tensor old_margins = torch::tensor({1.2f});
  MarginUpdate update;
  update.steps = 1;
  EXPECT_NEAR(train_new_margins(logits, labels, old_margins, torch::tensor({1.2f}), rows, update).item<double>(), 1.6,
              1e-6);
  update.steps = 2;
  const double p1 = 1.0 / (1.0 + std::exp(-3.2));
  const double buffer = 0.9 * -4.0 + 0.1 * (p1 - 1.0) * 8.0;
  int steps_seen = 0;
  const torch::Tensor trained = train_new_margins(logits, labels, old_margins, torch::tensor({1.2f}), rows, update,
                                                  [&](int step, double, double constraint) {
                                                    steps_seen = step;
                                                    EXPECT_EQ(constraint, 0.0);
                                                  });
  EXPECT_NEAR(trained.item<double>(), 1.6 - 0.1 * buffer, 1e-5);
  EXPECT_EQ(steps_seen, 2);
  EXPECT_FALSE(old_margins.requires_grad());
}

ParameterSet tiny_adbs_params(const std::string& session_steps) {
  ParameterSet params;
  params.set("pretrain_epochs", "2");
  params.set("batch_size", "32");
  params.set("adbs_session_steps", session_steps);
  return params;
}

TEST(AdbsMethod, ScoresTestsWithTheMarginMagnitudes) {
  torch::manual_seed(3);
  AdbsMethod method(tiny_adbs_params("10"));
  RunContext context = tiny_context(3);
  method.train_base(tiny_base(), context);
  const torch::Tensor embeddings = torch::randn({4, 256});
  const torch::Tensor before = method.classify(embeddings);
  const MethodState state = method.save_state();
  // Negating every margin leaves the test logits alone: they use |m_c|.
  MethodState flipped = state;
  flipped["boundaries.margin"] = -state.at("boundaries.margin");
  method.restore_state(flipped, context);
  EXPECT_TRUE(torch::allclose(method.classify(embeddings), before));
  // Doubling them doubles the logits.
  flipped["boundaries.margin"] = 2 * state.at("boundaries.margin");
  method.restore_state(flipped, context);
  EXPECT_TRUE(torch::allclose(method.classify(embeddings), 2 * before, 1e-5, 1e-5));
}

TEST(AdbsMethod, ASessionAddsMeanRowsAndTrainsOnlyItsNewMargins) {
  torch::manual_seed(4);
  RunContext context = tiny_context(4);
  AdbsMethod untrained(tiny_adbs_params("0"));
  const SessionData tiny = tiny_base();
  untrained.train_base(tiny, context);
  const MethodState base = untrained.save_state();
  const torch::Tensor base_margins = base.at("boundaries.margin").slice(0, 0, 6);
  // The base rows are the base classes' plain mean embeddings.
  const torch::Tensor base_embeddings = untrained.embed_rows(tiny.features);
  EXPECT_TRUE(torch::allclose(base.at("classifier.weight").slice(0, 0, 6),
                              class_means(base_embeddings, tiny.labels, {0, 1, 2, 3, 4, 5}), 1e-5, 1e-6));

  const SessionData support = tiny_support(6);
  // Without steps the new margins are the mean of the base ones, the new rows the shots' means.
  untrained.learn_session(support, context);
  const MethodState start = untrained.save_state();
  const torch::Tensor mean = base_margins.mean();
  EXPECT_TRUE(torch::allclose(start.at("boundaries.margin").slice(0, 6, 8), mean.expand({2})));
  EXPECT_TRUE(torch::allclose(start.at("classifier.weight").slice(0, 6, 8),
                              class_means(untrained.embed_rows(support.features), support.labels, {6, 7}), 1e-5, 1e-6));
  // Margins of classes not yet seen are as the base left them (its weight decay reaches them, as
  // the reference's one SGD over every parameter does).
  EXPECT_TRUE(torch::equal(start.at("boundaries.margin").slice(0, 8, 10), base.at("boundaries.margin").slice(0, 8, 10)));

  // With steps, the same base: only margins 6 and 7 move, and the rows are those of no steps.
  AdbsMethod trained(tiny_adbs_params("10"));
  RunContext other = tiny_context(4);
  trained.restore_state(base, other);
  trained.learn_session(support, other);
  const MethodState after = trained.save_state();
  EXPECT_TRUE(torch::equal(after.at("boundaries.margin").slice(0, 0, 6), base_margins));
  EXPECT_FALSE(torch::allclose(after.at("boundaries.margin").slice(0, 6, 8), mean.expand({2})));
  EXPECT_TRUE(torch::equal(after.at("classifier.weight"), start.at("classifier.weight")));
  EXPECT_TRUE(torch::equal(after.at("encoder.conv1.weight"), base.at("encoder.conv1.weight")));
  ASSERT_EQ(other.training_log.size(), 10u);
  EXPECT_EQ(other.training_log.back().stage, "session");
  EXPECT_GT(other.diagnostics.at("margin_novel_mean"), 0.0);
}

TEST(AdbsMethod, CountsItsMarginsAsTheParametersSessionsTrain) {
  torch::manual_seed(5);
  AdbsMethod method(tiny_adbs_params("2"));
  RunContext context = tiny_context(5);
  method.train_base(tiny_base(), context);
  method.learn_session(tiny_support(6), context);
  const ModelCost cost = method.inference_cost(context.input);
  EXPECT_EQ(cost.trainable_parameters(), 10);  // one margin per class of the protocol
  const std::int64_t rows = 10 * 256;
  std::int64_t encoder = 0;
  for (const auto& layer : cost.layers()) {
    if (layer.name.rfind("encoder", 0) == 0) encoder += layer.parameters;
  }
  EXPECT_EQ(cost.parameters(), encoder + rows + 10);
  EXPECT_EQ(cost.macs_of("scale"), 8);  // one product per seen class
}

TEST(AdbsMethod, KeepsTheBestBaseEpochOnValidationWhenAsked) {
  torch::manual_seed(6);
  ParameterSet params = tiny_adbs_params("2");
  params.set("pretrain_epochs", "3");
  AdbsMethod method(params);
  RunContext context = tiny_context(6);
  const SessionData validation = tiny_base();
  context.validation = &validation;
  context.selection = EpochSelection::validation;
  method.train_base(tiny_base(), context);
  const double kept = context.diagnostics.at("base_kept_epoch");
  EXPECT_GE(kept, 1);
  EXPECT_LE(kept, 3);
  double best = 0;
  for (const auto& epoch : context.training_log) best = std::max(best, epoch.values.at("selection_score"));
  EXPECT_EQ(context.diagnostics.at("base_selection_score"), best);
}

}  // namespace
}  // namespace fscil
