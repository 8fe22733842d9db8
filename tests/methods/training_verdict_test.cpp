// Every method's base session scores base validation after each epoch of the stages that make its
// base classifier (the training verdict's input, metrics/convergence.h), and that scoring changes
// nothing it trains: the same state, to the bit, as a run without a validation split.
#include <gtest/gtest.h>

#include <optional>

#include <map>
#include <set>

#include "methods/common/supervised_training.h"
#include "methods/method_registry.h"
#include "methods/orco/orco_settings.h"
#include "methods/pits_sc/pits_sc_settings.h"
#include "metrics/convergence.h"
#include "core/parameter_set.h"
#include "protocols/profiles.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet verdict_training() {
  ParameterSet params;
  for (const auto& [key, value] : std::map<std::string, std::string>{
           {"pretrain_epochs", "2"}, {"pit_episodes", "2"}, {"pit_epochs", "2"}, {"batch_size", "32"},
           {"orco_base_epochs", "2"}, {"orco_views", "2"}, {"orco_target_steps", "50"},
           {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"}, {"pan_pit_episodes", "2"},
           {"pan_pit_epochs", "1"}, {"pa_pct_epochs", "2"}, {"pa_pct_episodes", "2"}, {"ldc_calibration_epochs", "2"}}) {
    params.set(key, value);
  }
  return params;
}

MethodState trained_base(const std::string& name, const SessionData* validation, RunContext& context) {
  torch::manual_seed(9);
  const std::unique_ptr<Method> method = create_method(name, verdict_training());
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
  EXPECT_EQ(scored_stages.at("pa-pct"), (std::set<std::string>{"temporary_standard", "standard", "pcts"}));
  for (const std::string name : {"adbs", "dsn", "comp-fscil", "arp", "amfo", "ldc"}) {
    EXPECT_EQ(scored_stages.at(name), (std::set<std::string>{"base"})) << name;
  }
}

// Every fifth sample of `base`: scored on samples it trains on, the tiny base climbs to a plateau;
// on held-out noise (tiny_validation) its accuracy only wanders, and an early lucky epoch leaves no
// plateau to find.
SessionData every_fifth_sample(const SessionData& base) {
  const torch::Tensor every_fifth = torch::arange(0, base.labels.size(0), 5);
  SessionData part = base;
  part.features = base.features.gather(every_fifth);
  part.signals = base.signals.gather(every_fifth);
  part.labels = base.labels.index_select(0, every_fifth);
  return part;
}

// `stage`'s epochs in the log of `method`'s base session on the tiny base, scored on every fifth
// of its samples, from seed `seed`; `converged` sets base_stop=converged.
struct StageRun {
  std::vector<EpochLog> epochs;
  std::map<std::string, double> diagnostics;
};
StageRun stage_run(const std::string& method, ParameterSet params, const std::string& stage, bool converged,
                   std::uint64_t seed) {
  torch::manual_seed(seed);
  const SessionData base = tiny_base();
  const SessionData validation = every_fifth_sample(base);
  if (converged) params.set("base_stop", "converged");
  RunContext context = tiny_context(seed);
  context.validation = &validation;
  torch::manual_seed(seed);
  create_method(method, params)->train_base(base, context);
  StageRun run{{}, context.diagnostics};
  for (const EpochLog& row : context.training_log) {
    if (row.stage == stage) run.epochs.push_back(row);
  }
  return run;
}

// The first epoch, from epoch `least` on, after which `stage` has levelled off in `epochs`; 0 for none.
std::size_t first_level_epoch(const std::vector<EpochLog>& epochs, const std::string& stage, std::size_t least) {
  for (std::size_t e = std::max<std::size_t>(least, 1); e <= epochs.size(); ++e) {
    if (stage_has_levelled_off(std::vector<EpochLog>(epochs.begin(), epochs.begin() + e), stage)) return e;
  }
  return 0;
}

// base_stop=converged ends `stage` at the first epoch, from its least (`least`) on, at which it has
// levelled off (converged over a full window, on a plateau), and until then trains exactly as the
// whole schedule of `cap` epochs does; `when_converged` are the stopped run's settings besides
// base_stop. Whether the tiny stage levels off before its cap depends on the kernels' rounding
// (OpenBLAS's Haswell and Cooperlake kernels differ): the first of `seeds` whose whole schedule
// levels off (before `least`, with one) is the one checked.
void expect_stop_at_first_level_epoch(const std::string& method, const ParameterSet& params,
                                      const std::string& stage, std::size_t cap, const std::vector<std::uint64_t>& seeds,
                                      std::size_t least = 0,
                                      const std::map<std::string, std::string>& when_converged = {}) {
  std::optional<StageRun> whole;
  std::uint64_t seed = 0;
  std::size_t expected = 0;
  for (const std::uint64_t candidate : seeds) {
    StageRun run = stage_run(method, params, stage, false, candidate);
    ASSERT_EQ(run.epochs.size(), cap);
    expected = first_level_epoch(run.epochs, stage, least);
    // With a least, only a stage that levels off before it shows that the stop waits.
    const bool waits = least == 0 || first_level_epoch(run.epochs, stage, 0) < least;
    if (expected > 0 && expected < cap && waits) {
      whole = std::move(run);
      seed = candidate;
      break;
    }
  }
  ASSERT_TRUE(whole.has_value()) << "the tiny " << stage << " stage levelled off from none of the seeds";
  ParameterSet stopping = params;
  for (const auto& [key, value] : when_converged) stopping.set(key, value);
  const StageRun stopped = stage_run(method, stopping, stage, true, seed);
  const std::size_t epochs = stopped.epochs.size();
  ASSERT_EQ(epochs, expected) << "the stop came after another epoch than the first level one from " << least;
  ASSERT_GE(epochs, 2u * kConvergenceWindow);
  EXPECT_EQ(stopped.diagnostics.at(stage + "_converged_epoch"), static_cast<double>(epochs));
  for (std::size_t e = 0; e < epochs; ++e) {
    EXPECT_EQ(stopped.epochs[e].values.at("loss"), whole->epochs[e].values.at("loss")) << e;
    EXPECT_EQ(stopped.epochs[e].values.at(kBaseValidationKey), whole->epochs[e].values.at(kBaseValidationKey)) << e;
  }
  EXPECT_EQ(run_verdict(judge_stages(stopped.epochs)), TrainingVerdict::converged);
}

TEST(TrainingVerdict, BaseStopConvergedEndsTheStageAtItsFirstLevelEpochAndChangesNothingBefore) {
  ParameterSet params = verdict_training();
  params.set("pretrain_epochs", "10");  // it levels off after 6; a step decay's rates do not depend on the cap
  params.set("lr_step", "4");
  expect_stop_at_first_level_epoch("prototype", params, "base", 10, {11, 12, 13, 14});
}

// pits-sc's pseudo-incremental stage (every cop-fscil row's too) stops the same way.
TEST(TrainingVerdict, BaseStopConvergedEndsThePseudoIncrementalStageAtItsFirstLevelEpoch) {
  ParameterSet params = verdict_training();  // its 2-epoch pretraining is too short to stop
  params.set("pit_epochs", "8");
  expect_stop_at_first_level_epoch("pits-sc", params, "pseudo-incremental", 8, {12, 13, 14, 15});
}

// So does PA-PCT's PCTS, its released 10 epochs the cap (here 8).
TEST(TrainingVerdict, BaseStopConvergedEndsPaPctsPctsAtItsFirstLevelEpoch) {
  ParameterSet params = verdict_training();
  params.set("pa_pct_epochs", "8");
  expect_stop_at_first_level_epoch("pa-pct", params, "pcts", 8, {12, 13, 14, 15, 16, 17});
}

// OrCo's projector phase stops the same way, but never before its released length (orco_base_epochs,
// here 8 of a cap of 14): the first level epoch from the eighth on. Its constant rate makes the
// first 8 epochs those of the released schedule.
TEST(TrainingVerdict, BaseStopConvergedEndsOrcosProjectorAtItsFirstLevelEpochFromItsReleasedLength) {
  ParameterSet params = verdict_training();  // its 2-epoch pretraining is too short to stop
  params.set("orco_base_epochs", "14");
  expect_stop_at_first_level_epoch("orco", params, "projector", 14, {12, 13, 14, 15, 16, 17}, 8,
                                   {{"orco_base_epochs", "8"}, {"orco_base_epochs_cap", "14"}});
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
  // OrCo's projector runs at least its released 10 epochs, at most 30; plan counts the 10. The
  // paper profile runs exactly the 10 and never reads the cap.
  const OrcoSettings fast_orco = OrcoSettings::from(fast_pits);
  EXPECT_EQ(fast_orco.base.levelled_off_stop_from, 10);
  EXPECT_EQ(fast_orco.base.epochs, 30);
  const OrcoSettings paper_orco = OrcoSettings::from(paper);
  EXPECT_EQ(paper_orco.base.levelled_off_stop_from, 0);
  EXPECT_EQ(paper_orco.base.epochs, 10);
  EXPECT_EQ(paper.used().count("orco_base_epochs_cap"), 0u);
}

}  // namespace
}  // namespace fscil
