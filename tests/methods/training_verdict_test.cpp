// Every method's base session scores base validation after each epoch of the stages that make its
// base classifier (the training verdict's input, metrics/convergence.h), and that scoring changes
// nothing it trains: the same state, to the bit, as a run without a validation split.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "methods/common/supervised_training.h"
#include "methods/method_registry.h"
#include "methods/pits_sc/pits_sc_settings.h"
#include "metrics/convergence.h"
#include "core/parameter_set.h"
#include "protocols/profiles.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet short_training() {
  ParameterSet params;
  for (const auto& [key, value] : std::map<std::string, std::string>{
           {"pretrain_epochs", "2"}, {"pit_episodes", "2"}, {"pit_epochs", "2"}, {"batch_size", "32"},
           {"orco_base_epochs", "2"}, {"orco_views", "2"}, {"orco_target_steps", "50"},
           {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"}, {"pan_pit_episodes", "2"},
           {"pan_pit_epochs", "1"}}) {
    params.set(key, value);
  }
  return params;
}

MethodState trained_base(const std::string& name, const SessionData* validation, RunContext& context) {
  torch::manual_seed(9);
  const std::unique_ptr<Method> method = create_method(name, short_training());
  context.validation = validation;
  method->train_base(tiny_base(), context);
  return method->save_state();
}

TEST(TrainingVerdict, EveryMethodScoresBaseValidationEachEpochWithoutChangingWhatItTrains) {
  const SessionData validation = tiny_validation();
  std::map<std::string, std::set<std::string>> scored_stages;
  for (const std::string& name : resolve_method_names("all")) {
    RunContext scored = tiny_context(9), unscored = tiny_context(9);
    const MethodState with = trained_base(name, &validation, scored);
    const MethodState without = trained_base(name, nullptr, unscored);
    ASSERT_EQ(with.size(), without.size()) << name;
    for (const auto& [key, tensor] : with) {
      EXPECT_TRUE(torch::equal(tensor, without.at(key))) << name << ": " << key << " depends on the scoring";
    }
    const std::vector<StageConvergence> stages = judge_stages(scored.training_log);
    EXPECT_TRUE(judge_stages(unscored.training_log).empty()) << name;
    ASSERT_FALSE(stages.empty()) << name << " scores no stage";
    for (const auto& stage : stages) {
      EXPECT_EQ(stage.epochs, 2) << name << ", " << stage.stage;  // every epoch of the stage
      EXPECT_GE(stage.last, 0.0);
      EXPECT_LE(stage.last, 100.0);
      scored_stages[name].insert(stage.stage);
    }
  }
  // The stages each method's base classifier comes from.
  EXPECT_EQ(scored_stages.at("prototype"), (std::set<std::string>{"base"}));
  EXPECT_EQ(scored_stages.at("pits-sc"), (std::set<std::string>{"pretrain", "pseudo-incremental"}));
  EXPECT_EQ(scored_stages.at("orco"), (std::set<std::string>{"pretrain", "projector"}));
  EXPECT_EQ(scored_stages.at("pan"), (std::set<std::string>{"temporary_standard", "standard"}));
  for (const std::string name : {"adbs", "dsn", "comp-fscil", "arp", "amfo"}) {
    EXPECT_EQ(scored_stages.at(name), (std::set<std::string>{"base"})) << name;
  }
}

// base_stop=converged ends a stage at the first epoch at which it has levelled off (converged over
// a full window, on a plateau), and until then trains exactly as the whole schedule does.
TEST(TrainingVerdict, BaseStopConvergedEndsTheStageAtItsFirstLevelEpochAndChangesNothingBefore) {
  // Scored on every fifth sample it trains on, the tiny base climbs to a plateau; on held-out noise
  // (tiny_validation) its accuracy only wanders, and an early lucky epoch leaves no plateau to find.
  torch::manual_seed(11);
  const SessionData base = tiny_base();
  const torch::Tensor every_fifth = torch::arange(0, base.labels.size(0), 5);
  SessionData validation = base;
  validation.features = base.features.gather(every_fifth);
  validation.signals = base.signals.gather(every_fifth);
  validation.labels = base.labels.index_select(0, every_fifth);
  ParameterSet params = short_training();
  params.set("pretrain_epochs", "30");
  params.set("lr_step", "4");
  const auto train = [&](const ParameterSet& chosen, RunContext& context) {
    torch::manual_seed(11);
    const std::unique_ptr<Method> method = create_method("prototype", chosen);
    context.validation = &validation;
    method->train_base(base, context);
  };
  RunContext whole = tiny_context(11), stopped = tiny_context(11);
  train(params, whole);
  ParameterSet stopping = params;
  stopping.set("base_stop", "converged");
  train(stopping, stopped);
  ASSERT_EQ(whole.training_log.size(), 30u);
  const std::size_t epochs = stopped.training_log.size();
  ASSERT_LT(epochs, 30u) << "the tiny base never converged";
  ASSERT_GE(epochs, 2u * kConvergenceWindow);
  EXPECT_EQ(stopped.diagnostics.at("base_converged_epoch"), static_cast<double>(epochs));
  for (std::size_t e = 0; e < epochs; ++e) {
    EXPECT_EQ(stopped.training_log[e].values.at("loss"), whole.training_log[e].values.at("loss")) << e;
    const std::vector<EpochLog> so_far(whole.training_log.begin(), whole.training_log.begin() + e + 1);
    EXPECT_EQ(stage_has_levelled_off(so_far, "base"), e + 1 == epochs) << "epoch " << e + 1;
  }
  EXPECT_EQ(run_verdict(judge_stages(stopped.training_log)), TrainingVerdict::converged);
}

// The fast profile trains every base stage until it has converged, at most 40 epochs, and plan counts
// such a stage at the epoch where they typically stopped; a fixed schedule at its length.
TEST(TrainingVerdict, TheFastProfileStopsBaseStagesOnceConvergedAndPlanCountsTheTypicalStop) {
  ParameterSet fast;
  apply_profile("fast", fast);
  const SupervisedSchedule converging = SupervisedSchedule::from(fast);
  EXPECT_TRUE(converging.stop_when_converged);
  EXPECT_EQ(converging.epochs, 40);
  EXPECT_EQ(converging.lr_step, 4);
  EXPECT_EQ(converging.expected_epochs(), kTypicalConvergedEpoch);
  fast.set("pretrain_epochs", "8");
  EXPECT_EQ(SupervisedSchedule::from(fast).expected_epochs(), 8);  // a cap below the typical stop
  fast.set("base_stop", "schedule");
  fast.set("pretrain_epochs", "40");
  EXPECT_EQ(SupervisedSchedule::from(fast).expected_epochs(), 40);
  ParameterSet paper;
  apply_profile("paper", paper);
  EXPECT_FALSE(SupervisedSchedule::from(paper).stop_when_converged);
  // The pseudo-incremental stage of pits-sc (and of cop-fscil's rows) stops the same way, capped
  // at the released 10 epochs, which plan counts in full: the cap is below the typical stop.
  ParameterSet fast_pits;
  apply_profile("fast", fast_pits);
  const PitsScSettings pits = PitsScSettings::from(fast_pits);
  EXPECT_TRUE(pits.pit.stop_when_converged);
  EXPECT_EQ(pits.pit.epochs, 10);
  EXPECT_EQ(pits.pit.expected_epochs(), 10);
}

// pits-sc's pseudo-incremental stage ends at its first level epoch under base_stop=converged, as
// a pretraining does, and trains exactly as the whole stage until then.
TEST(TrainingVerdict, BaseStopConvergedEndsThePseudoIncrementalStageAtItsFirstLevelEpoch) {
  torch::manual_seed(12);
  const SessionData base = tiny_base();
  const torch::Tensor every_fifth = torch::arange(0, base.labels.size(0), 5);
  SessionData validation = base;
  validation.features = base.features.gather(every_fifth);
  validation.signals = base.signals.gather(every_fifth);
  validation.labels = base.labels.index_select(0, every_fifth);
  ParameterSet params = short_training();
  params.set("pit_epochs", "12");
  const auto pseudo_incremental_log = [&](const ParameterSet& chosen, RunContext& context) {
    torch::manual_seed(12);
    const std::unique_ptr<Method> method = create_method("pits-sc", chosen);
    context.validation = &validation;
    method->train_base(base, context);
    std::vector<EpochLog> log;
    for (const EpochLog& row : context.training_log) {
      if (row.stage == "pseudo-incremental") log.push_back(row);
    }
    return log;
  };
  RunContext whole_context = tiny_context(12), stopped_context = tiny_context(12);
  const std::vector<EpochLog> whole = pseudo_incremental_log(params, whole_context);
  ParameterSet stopping = params;
  stopping.set("base_stop", "converged");  // the 2-epoch pretraining is too short to stop
  const std::vector<EpochLog> stopped = pseudo_incremental_log(stopping, stopped_context);
  ASSERT_EQ(whole.size(), 12u);
  ASSERT_LT(stopped.size(), 12u) << "the tiny pseudo-incremental stage never levelled off";
  ASSERT_GE(stopped.size(), 2u * kConvergenceWindow);
  EXPECT_EQ(stopped_context.diagnostics.at("pseudo-incremental_converged_epoch"),
            static_cast<double>(stopped.size()));
  for (std::size_t e = 0; e < stopped.size(); ++e) {
    EXPECT_EQ(stopped[e].values.at("loss"), whole[e].values.at("loss")) << e;
    EXPECT_EQ(stopped[e].values.at(kBaseValidationKey), whole[e].values.at(kBaseValidationKey)) << e;
    const std::vector<EpochLog> so_far(whole.begin(), whole.begin() + e + 1);
    EXPECT_EQ(stage_has_levelled_off(so_far, "pseudo-incremental"), e + 1 == stopped.size()) << "epoch " << e + 1;
  }
}

}  // namespace
}  // namespace fscil
