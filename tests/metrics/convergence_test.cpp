#include "metrics/convergence.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fscil {
namespace {

// A stage's log rows with a base-validation accuracy after each epoch, and one row without.
std::vector<EpochLog> scored(const std::string& stage, const std::vector<double>& accuracy) {
  std::vector<EpochLog> log;
  for (std::size_t e = 0; e < accuracy.size(); ++e) {
    log.push_back({stage, static_cast<int>(e + 1), {{"loss", 1.0 / static_cast<double>(e + 1)}, {kBaseValidationKey, accuracy[e]}}});
  }
  return log;
}

TEST(Convergence, RisingLastEpochsAreStillRisingByTheBestAgainstTheBestBefore) {
  // AMFO-like: the last three epochs' best (80) against the best of the first five (71): +9.
  const auto stages = judge_stages(scored("base", {20, 35, 50, 62, 71, 74, 78, 80}));
  ASSERT_EQ(stages.size(), 1u);
  EXPECT_EQ(stages[0].verdict, TrainingVerdict::still_rising);
  EXPECT_EQ(stages[0].window, 3);
  EXPECT_DOUBLE_EQ(stages[0].rise, 9.0);
  EXPECT_DOUBLE_EQ(stages[0].first, 20.0);
  EXPECT_DOUBLE_EQ(stages[0].last, 80.0);
  EXPECT_EQ(run_verdict(stages), TrainingVerdict::still_rising);
  EXPECT_EQ(describe_stage(stages[0]),
            "base: best of its last 3 of 8 epochs +9.00 points against the best before (20.0% -> 80.0%)");
}

// temperature=1e-45 once trained at chance, loss 2.3026 = ln 10 every epoch, and was filed in the
// stage cache: a loss that never moves is no training, whatever its length.
TEST(Convergence, ALossThatNeverMovesIsNotLearning) {
  std::vector<EpochLog> log;
  for (int epoch = 1; epoch <= 3; ++epoch) {
    log.push_back({"pretrain", epoch, {{"loss", std::log(10.0) * (1 + 1e-6 * epoch)}, {kBaseValidationKey, 10.0}}});
  }
  auto stages = judge_stages(log);
  ASSERT_EQ(stages.size(), 1u);
  EXPECT_EQ(stages[0].verdict, TrainingVerdict::not_learning);
  EXPECT_EQ(run_verdict(stages), TrainingVerdict::not_learning);
  EXPECT_TRUE(ended_unfinished(stages[0].verdict));
  EXPECT_EQ(describe_stage(stages[0]),
            "pretrain: its loss stayed at 2.3026 over all its epochs, not learning (10.0% on base validation)");
  // A loss that moves by more than kFlatLossFraction is judged as before (here, too few epochs).
  log[2].values["loss"] = std::log(10.0) * (1 - 2 * kFlatLossFraction);
  EXPECT_EQ(judge_stages(log)[0].verdict, TrainingVerdict::unjudged);
  // One epoch cannot show a loss that never moves.
  log.resize(1);
  EXPECT_EQ(judge_stages(log)[0].verdict, TrainingVerdict::unjudged);
  // Not learning outweighs still rising in a run of several stages.
  auto rising = judge_stages(scored("base", {20, 35, 50, 62, 71, 74, 78, 80}));
  rising.push_back(stages[0]);
  EXPECT_EQ(run_verdict(rising), TrainingVerdict::not_learning);
}

TEST(Convergence, ANoisyPlateauOrALateDipIsConverged) {
  // Within a point of the earlier best: noise, not a rise (0.9 < 1).
  const auto plateau = judge_stages(scored("pretrain", {60, 90, 95.1, 94.0, 95.5, 96.0, 95.2, 96.4}));
  EXPECT_EQ(plateau[0].verdict, TrainingVerdict::converged);
  EXPECT_NEAR(plateau[0].rise, 0.9, 1e-12);
  // A dip at the end is no rise either: -5 points.
  const auto dip = judge_stages(scored("base", {50, 80, 90, 85, 84, 83}));
  EXPECT_EQ(dip[0].verdict, TrainingVerdict::converged);
  EXPECT_DOUBLE_EQ(dip[0].rise, -5.0);
  // Exactly one point is rising: the threshold is inclusive.
  EXPECT_EQ(judge_stages(scored("base", {50, 55, 60, 58, 61, 59}))[0].verdict, TrainingVerdict::still_rising);
}

TEST(Convergence, AStageLevelsOffOnAPlateauNotInADip) {
  // The dip above is converged, but no place to stop: DSN's base on simtex (76.8% after its second
  // epoch at a rate of 0.1, 72.5% after its sixth at 0.05) would have kept its dip.
  EXPECT_FALSE(stage_has_levelled_off(scored("base", {50, 80, 90, 85, 84, 83}), "base"));
  EXPECT_FALSE(stage_has_levelled_off(scored("base", {50, 80, 90, 88, 89, 89}), "base"));  // -1: still a dip
  EXPECT_TRUE(stage_has_levelled_off(scored("base", {50, 80, 90, 88, 89, 89.5}), "base"));
  EXPECT_TRUE(stage_has_levelled_off(scored("base", {50, 80, 90, 88, 89, 90.9}), "base"));
  EXPECT_FALSE(stage_has_levelled_off(scored("base", {50, 80, 90, 88, 89, 91}), "base"));  // rising
  // Converged, but the epoch a stop keeps is a point or more below the best: a dip, not the plateau.
  EXPECT_FALSE(stage_has_levelled_off(scored("base", {50, 80, 90, 89.5, 90.5, 89.5}), "base"));
  EXPECT_TRUE(stage_has_levelled_off(scored("base", {50, 80, 90, 89.5, 90.5, 89.6}), "base"));
  // PITS-SC's pretraining, simtex seed 1 (fairness table): stopped here, at 75.1% after 78.2%.
  EXPECT_FALSE(stage_has_levelled_off(scored("pretrain", {14.9, 70.5, 70.9, 78.2, 73.1, 78.1, 75.1}), "pretrain"));
  EXPECT_FALSE(stage_has_levelled_off(scored("base", {50, 80, 90, 88, 89, 89.5}), "pretrain"));  // no such stage
}

TEST(Convergence, StagesShorterThanTwoWindowsAreUnjudgedAndEmptySplitsAreSkipped) {
  // Five epochs: a window of 3 against 2 before it would be noise.
  const auto five = judge_stages(scored("projector", {40, 70, 80, 90, 99}));
  EXPECT_EQ(five[0].verdict, TrainingVerdict::unjudged);
  EXPECT_EQ(five[0].window, 0);
  EXPECT_EQ(run_verdict(five), TrainingVerdict::unjudged);
  EXPECT_EQ(describe_stage(five[0]), "projector: 5 scored epochs, too few to judge (99.0%)");
  EXPECT_FALSE(stage_has_levelled_off(scored("projector", {90, 90, 90, 90, 90}), "projector"));
  EXPECT_TRUE(stage_has_levelled_off(scored("projector", {90, 90, 90, 90, 90, 90}), "projector"));
  // An epoch scored on an empty split (not a number) is left out, not judged.
  const auto gap = judge_stages(scored("base", {50, 60, 70, std::nan(""), 80, 80, 80}));
  EXPECT_EQ(gap[0].epochs, 6);
  EXPECT_EQ(gap[0].verdict, TrainingVerdict::still_rising);
}

TEST(Convergence, EveryScoredStageIsJudgedInOrderAndUnscoredRowsAreSkipped) {
  std::vector<EpochLog> log = scored("pretrain", {50, 70, 80.5, 81, 81, 81});
  log.push_back({"pseudo-incremental", 1, {{"loss", 2.0}}});  // not scored
  for (const auto& row : scored("projector", {10, 20, 30, 40, 50, 60})) log.push_back(row);
  const auto stages = judge_stages(log);
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[0].stage, "pretrain");
  EXPECT_EQ(stages[0].verdict, TrainingVerdict::converged);
  EXPECT_EQ(stages[1].stage, "projector");
  EXPECT_EQ(stages[1].epochs, 6);
  EXPECT_EQ(stages[1].verdict, TrainingVerdict::still_rising);
  EXPECT_EQ(run_verdict(stages), TrainingVerdict::still_rising);
  EXPECT_EQ(run_verdict(judge_stages({{"base", 1, {{"loss", 1.0}}}})), TrainingVerdict::not_recorded);
  EXPECT_STREQ(verdict_name(TrainingVerdict::still_rising), "still rising");
}

}  // namespace
}  // namespace fscil
