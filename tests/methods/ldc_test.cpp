// LDC's parts against hand-computed values, and its base and sessions on the tiny protocol.
#include <gtest/gtest.h>

#include <cmath>

#include "core/parameter_set.h"
#include "methods/common/class_statistics.h"
#include "methods/ldc/calibration_unit.h"
#include "methods/ldc/distribution_memory.h"
#include "methods/ldc/ldc_method.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

TEST(LdcCalibrationLoss, SumsEachUpdatesKlFromTheRealRowsSoftmax) {
  // softmax(0, ln 3) = (1/4, 3/4) against softmax(0, 0) = (1/2, 1/2):
  // 1/4 ln(1/2) + 3/4 ln(3/2) = 0.130812 per update.
  const torch::Tensor real = torch::tensor({{0.0f, static_cast<float>(std::log(3.0))}});
  const torch::Tensor flat = torch::zeros({1, 2});
  EXPECT_NEAR(calibration_loss({flat}, real).item<double>(), 0.130812, 1e-5);
  EXPECT_NEAR(calibration_loss({flat, flat}, real).item<double>(), 2 * 0.130812, 1e-5);
  EXPECT_NEAR(calibration_loss({real, real + 5}, real).item<double>(), 0.0, 1e-6);  // softmax ignores a shift
}

TEST(LdcCalibrationUnit, EachUpdateFeedsTheNext) {
  torch::manual_seed(3);
  CalibrationUnit unit(4);
  const torch::Tensor x = torch::rand({5, 4});
  const std::vector<torch::Tensor> three = unit->updates(x, 3);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_TRUE(torch::equal(unit->updates(three[0], 1)[0], three[1]));
  EXPECT_TRUE(torch::equal(unit->updates(three[1], 1)[0], three[2]));
  EXPECT_GE(three[2].min().item<float>(), 0.0f);  // each layer ends in a ReLU
}

TEST(LdcDistributionMemory, FoldsASessionsClassesOneAfterAnotherAndDrawsFromTheSharedCovariance) {
  DistributionMemory memory(4, 3, 2);
  const torch::Tensor eye = torch::eye(2);
  memory->start_covariance(torch::stack({2 * eye, 4 * eye}));
  EXPECT_TRUE(torch::allclose(memory->covariance(), 3 * eye));
  // Two base classes, a session of two: (3 I 2 + I 2) / 4 = 2 I, then (2 I 2 + 5 I 2) / 4 = 3.5 I.
  memory->fold_covariances(torch::stack({eye, 5 * eye}), 2);
  EXPECT_TRUE(torch::allclose(memory->covariance(), 3.5 * eye)) << memory->covariance();

  torch::manual_seed(4);
  const torch::Tensor means = torch::tensor({{1.0f, -2.0f}, {10.0f, 0.0f}});
  const torch::Tensor draws = memory->draw(means, 20000);
  ASSERT_EQ(draws.sizes(), (std::vector<std::int64_t>{2, 20000, 2}));
  EXPECT_TRUE(torch::allclose(draws.mean(1), means, 0, 0.05)) << draws.mean(1);
  EXPECT_TRUE(torch::allclose(sample_covariance(draws[1]), 3.5 * eye, 0, 0.15)) << sample_covariance(draws[1]);

  // Each class keeps its first three draws; a removed class is replayed no more.
  memory->keep(0, draws);
  EXPECT_TRUE(torch::equal(memory->kept_features(2), torch::cat({draws[0].slice(0, 0, 3), draws[1].slice(0, 0, 3)})));
  memory->forget({0});
  EXPECT_TRUE(torch::equal(memory->kept_features(2), draws[1].slice(0, 0, 3)));
  EXPECT_TRUE(torch::equal(memory->kept_labels(2), torch::ones({3}, torch::kLong)));
}

ParameterSet tiny_ldc_params(int session_epochs) {
  ParameterSet params;
  params.set("pretrain_epochs", "1");
  params.set("batch_size", "32");
  params.set("ldc_calibration_epochs", "30");
  params.set("ldc_calibration_lr", "0.003");
  params.set("ldc_session_epochs", std::to_string(session_epochs));
  params.set("ldc_session_batch", "10");
  return params;
}

TEST(LdcMethod, TheBaseRowsAreTheClassMeansInUnitScaleAndTheUnitLearnsToCalibrate) {
  torch::manual_seed(5);
  LdcMethod method(tiny_ldc_params(0));
  RunContext context = tiny_context(5);
  const SessionData base = tiny_base();
  method.train_base(base, context);
  const torch::Tensor embeddings = method.embed_rows(base.features);
  EXPECT_NEAR(embeddings.square().mean().sqrt().item<double>(), 1.0, 1e-4);  // ldc_unit_rms
  const MethodState state = method.save_state();
  const auto [means, covariances] = class_statistics(embeddings, base.labels, {0, 1, 2, 3, 4, 5});
  EXPECT_TRUE(torch::allclose(state.at("classifier.weight").slice(0, 0, 6), means, 1e-4, 1e-6));
  EXPECT_TRUE(torch::allclose(state.at("memory.covariance"), covariances.mean(0), 1e-4, 1e-6));
  // 30 epochs of the unit after the one pretraining epoch; the matching loss falls.
  ASSERT_EQ(context.training_log.size(), 31u);
  EXPECT_EQ(context.training_log.back().stage, "calibration");
  EXPECT_LT(context.training_log.back().values.at("loss"), 0.6 * context.training_log[1].values.at("loss"));
}

TEST(LdcMethod, ASessionAddsTheShotMeansFoldsTheirCovariancesAndFineTunesEveryRow) {
  torch::manual_seed(6);
  LdcMethod still(tiny_ldc_params(0)), tuned(tiny_ldc_params(5));
  RunContext still_context = tiny_context(6);
  still.train_base(tiny_base(), still_context);
  torch::manual_seed(6);
  RunContext tuned_context = tiny_context(6);
  tuned.train_base(tiny_base(), tuned_context);
  const MethodState base = tuned.save_state();
  torch::manual_seed(7);
  const SessionData support = tiny_support(6);
  torch::manual_seed(8);
  still.learn_session(support, still_context);
  torch::manual_seed(8);
  tuned.learn_session(support, tuned_context);
  const MethodState before = still.save_state(), after = tuned.save_state();

  // Without fine-tuning the new rows are the shots' means, the base rows as they were, and the
  // shared covariance has folded in each new class's.
  const torch::Tensor shots = tuned.embed_rows(support.features);
  const auto [means, covariances] = class_statistics(shots, support.labels, {6, 7});
  EXPECT_TRUE(torch::allclose(before.at("classifier.weight").slice(0, 6, 8), means, 1e-4, 1e-6));
  EXPECT_TRUE(torch::equal(before.at("classifier.weight").slice(0, 0, 6), base.at("classifier.weight").slice(0, 0, 6)));
  torch::Tensor folded = base.at("memory.covariance");
  for (int c = 0; c < 2; ++c) folded = (folded * 6 + covariances[c] * 2) / 8;
  EXPECT_TRUE(torch::allclose(before.at("memory.covariance"), folded, 1e-4, 1e-6));
  EXPECT_GT(before.at("memory.kept").slice(0, 6, 8).abs().sum().item<double>(), 0.0);
  EXPECT_EQ(before.at("memory.kept").slice(0, 8, 10).abs().sum().item<double>(), 0.0);

  // Five epochs of fine-tuning move every seen row, base rows too, and no unseen row; the encoder
  // and the unit stay as they were.
  const torch::Tensor moved = (after.at("classifier.weight") - before.at("classifier.weight")).abs().sum(1);
  EXPECT_TRUE((moved.slice(0, 0, 8) > 0).all().item<bool>()) << moved;
  EXPECT_TRUE((moved.slice(0, 8, 10) == 0).all().item<bool>()) << moved;
  for (const auto& [name, tensor] : base) {
    if (name.rfind("encoder.", 0) == 0 || name.rfind("calibration_unit.", 0) == 0) {
      EXPECT_TRUE(torch::equal(after.at(name), tensor)) << name;
    }
  }
}

// A removed class's draws leave the fine-tuning data and its row takes no part: it does not move.
TEST(LdcMethod, ARemovedClassIsNeitherReplayedNorTuned) {
  torch::manual_seed(9);
  LdcMethod method(tiny_ldc_params(5));
  RunContext context = tiny_context(9);
  method.train_base(tiny_base(), context);
  method.forget_classes({0}, context);
  const MethodState before = method.save_state();
  method.learn_session(tiny_support(6), context);
  const MethodState after = method.save_state();
  EXPECT_TRUE(torch::equal(after.at("classifier.weight")[0], before.at("classifier.weight")[0]));
  EXPECT_FALSE(torch::equal(after.at("classifier.weight")[1], before.at("classifier.weight")[1]));
  EXPECT_TRUE(torch::equal(after.at("memory.removed").slice(0, 0, 2), torch::tensor({true, false})));
}

}  // namespace
}  // namespace fscil
