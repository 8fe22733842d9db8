// Stages of a base session that methods share (MethodEntry::shared_stages, RunContext::stages):
// pits-sc's pretraining is cop-fscil/cpi's to the bit, a run continuing from it ends as a run
// that trained it, and every value declared as read after it really leaves it as it was.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "methods/common/torch_random_state.h"
#include "methods/method_registry.h"
#include "methods/pan/pan_method.h"
#include "methods/pits_sc/pits_sc_method.h"
#include "methods/prototype/prototype_method.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_training.h"

namespace fscil {
namespace {

using Values = std::map<std::string, std::string>;
const std::string kStage = PitsScMethod::kPretrainingStage;

// Stages by name, as the runner keeps them for one run's identity; counts what a method asks.
class KeptStages : public StageStore {
 public:
  std::optional<TrainedStage> find(const std::string& stage) override {
    ++finds;
    const auto kept = stages.find(stage);
    if (kept == stages.end()) return std::nullopt;
    return kept->second;
  }
  void store(const std::string& stage, TrainedStage trained) override { stages[stage] = std::move(trained); }
  std::map<std::string, TrainedStage> stages;
  int finds = 0;
};

struct Trained {
  MethodState state;  // after the base session, or after a session when one was learned
  std::mt19937_64 generator;
  torch::Tensor torch_state;
  std::map<std::string, double> diagnostics;
  std::vector<EpochLog> training_log;
  torch::Tensor logits;  // of the base samples, after the last session learned
};

const Values kShortBase = {{"pretrain_epochs", "2"}, {"pit_episodes", "2"}, {"pit_epochs", "1"}, {"batch_size", "32"}};

Trained train(const std::string& method_name, const Values& values, StageStore* stages, bool with_session = false,
              EpochSelection selection = EpochSelection::last) {
  const std::unique_ptr<Method> method = tiny_method(method_name, values);
  RunContext context = tiny_context(5);
  const SessionData validation = tiny_base();
  context.validation = &validation;
  context.selection = selection;
  context.stages = stages;
  method->train_base(tiny_base(), context);
  Trained trained{{}, {}, {}, context.diagnostics, context.training_log, {}};
  if (with_session) method->learn_session(tiny_support(6), context);
  trained.state = method->save_state();
  trained.generator = context.generator;
  trained.torch_state = torch_random_state();
  trained.logits = method->logits(tiny_base().features.all());
  return trained;
}

// The epochs' values but their times.
std::vector<std::map<std::string, double>> logged_values(const std::vector<EpochLog>& log) {
  std::vector<std::map<std::string, double>> values;
  for (const EpochLog& epoch : log) {
    values.push_back(epoch.values);
    values.back().erase("seconds");
  }
  return values;
}

TEST(SharedPretraining, CpiContinuingFromPitsScsPretrainingEndsAsACpiThatTrainedIt) {
  KeptStages stages;
  train("pits-sc", kShortBase, &stages);
  ASSERT_EQ(stages.stages.count(kStage), 1u);
  const TrainedStage pits_pretraining = stages.stages.at(kStage);
  EXPECT_EQ(pits_pretraining.training_log.size(), 2u);  // its two epochs, nothing of the later stage
  EXPECT_EQ(pits_pretraining.state.at("context_bank.count").item<std::int64_t>(), 2 * 150);  // every map it trained on

  const Trained cold = train("cop-fscil/cpi", kShortBase, nullptr, true);
  const Trained shared = train("cop-fscil/cpi", kShortBase, &stages, true);
  expect_same_state(cold.state, shared.state, "cpi after pits-sc's pretraining and a session");
  EXPECT_EQ(shared.generator, cold.generator);
  EXPECT_TRUE(torch::equal(shared.torch_state, cold.torch_state));
  EXPECT_TRUE(torch::equal(shared.logits, cold.logits));
  EXPECT_EQ(shared.diagnostics, cold.diagnostics);
  EXPECT_EQ(logged_values(shared.training_log), logged_values(cold.training_log));

  // In the other order: cpi's own pretraining, as it files it, is pits-sc's.
  KeptStages cpi_first;
  train("cop-fscil/cpi", kShortBase, &cpi_first);
  expect_same_state(pits_pretraining.state, cpi_first.stages.at(kStage).state, "cpi's pretraining");
  EXPECT_EQ(cpi_first.stages.at(kStage).generator, pits_pretraining.generator);
  const Trained pits_cold = train("pits-sc", kShortBase, nullptr, true);
  const Trained pits_shared = train("pits-sc", kShortBase, &cpi_first, true);
  expect_same_state(pits_cold.state, pits_shared.state, "pits-sc after cpi's pretraining and a session");
  EXPECT_TRUE(torch::equal(pits_shared.logits, pits_cold.logits));
}

// What makes a pretraining not PITS-SC's: the method then neither asks for one nor files its own.
TEST(SharedPretraining, NoStageIsSharedWhereThePretrainingsDiffer) {
  const std::vector<std::pair<std::string, Values>> own_pretraining = {
      {"cop-fscil/cpi", {{"cpi_pretrain_coverage", "0.5"}}},  // CPI acts in pretraining
      {"cop-fscil/cpi", {{"cpi_space", "raw"}}},              // the bank holds other maps' statistics
      {"cop-fscil/cpi", {{"cpi_bank", "512"}}},
      {"cop-fscil/cpi+pcqa", {}},                              // the adapter trains with the encoder
      {"cop-fscil", {}}};
  for (const auto& [method, values] : own_pretraining) {
    Values all = kShortBase;
    all.insert(values.begin(), values.end());
    KeptStages stages;
    train(method, all, &stages);
    EXPECT_EQ(stages.finds, 0) << method;
    EXPECT_TRUE(stages.stages.empty()) << method;
  }
  // A kept epoch spans both stages, so a selection other than the last trains its own.
  KeptStages selected;
  train("pits-sc", kShortBase, &selected, false, EpochSelection::validation);
  EXPECT_EQ(selected.finds, 0);
  EXPECT_TRUE(selected.stages.empty());
}

// `filer`'s `stage` is `taker`'s to the bit: `taker` continuing from it ends as a `taker` that
// trained it, and with every value its entry declares as read after the stage changed (`changed`:
// each such value, another than `base`'s), it files the stage `filer` does.
void expect_stage_serves(const std::string& stage, const std::string& filer, const std::string& taker,
                         const Values& base, const Values& changed) {
  KeptStages stages;
  train(filer, base, &stages);
  ASSERT_EQ(stages.stages.count(stage), 1u);
  const Trained cold = train(taker, base, nullptr, true);
  const Trained shared = train(taker, base, &stages, true);
  EXPECT_EQ(stages.finds, 2);  // the filer's run asked too, and found none
  expect_same_state(cold.state, shared.state, taker + " after " + filer + "'s stage and a session");
  EXPECT_EQ(shared.generator, cold.generator);
  EXPECT_TRUE(torch::equal(shared.torch_state, cold.torch_state));
  EXPECT_TRUE(torch::equal(shared.logits, cold.logits));
  EXPECT_EQ(shared.diagnostics, cold.diagnostics);
  EXPECT_EQ(logged_values(shared.training_log), logged_values(cold.training_log));

  Values all_changed = base;
  std::set<std::string> tested;
  for (const auto& [key, value] : changed) {
    all_changed[key] = value;
    tested.insert(key);
  }
  ASSERT_EQ(method_entry(taker).shared_stages.at(stage), tested) << "each declared parameter needs a changed value here";
  KeptStages own;
  train(taker, all_changed, &own);
  const TrainedStage &filed = stages.stages.at(stage), &owned = own.stages.at(stage);
  expect_same_state(filed.state, owned.state, taker + "'s own stage");
  EXPECT_EQ(owned.generator, filed.generator);
  EXPECT_TRUE(torch::equal(owned.torch_random_state, filed.torch_random_state));
  EXPECT_EQ(logged_values(owned.training_log), logged_values(filed.training_log));
}

TEST(SharedPanStages, PaPctContinuingFromPansStagesEndsAsAPaPctThatTrainedThem) {
  expect_stage_serves(PanMethod::kBaseStages, "pan", "pa-pct",
                      {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"pan_pit_episodes", "2"},
                       {"pa_pct_epochs", "1"}, {"pa_pct_episodes", "2"}},
                      {{"pa_pct_epochs", "2"}, {"pa_pct_episodes", "3"}, {"pa_pct_alpha", "2"},
                       {"pa_pct_encoder_lr", "0.05"}, {"pa_pct_attention_lr", "0.001"}});
}

TEST(SharedCosinePretraining, LdcContinuingFromPrototypesPretrainingEndsAsAnLdcThatTrainedIt) {
  expect_stage_serves(PrototypeMethod::kPretrainingStage, "prototype", "ldc",
                      {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"ldc_calibration_epochs", "2"},
                       {"ldc_session_epochs", "2"}},
                      {{"ldc_calibration_epochs", "3"}, {"ldc_calibration_lr", "0.02"}, {"ldc_calibration_rounds", "2"},
                       {"ldc_calibration_samples", "20"}, {"ldc_unit_rms", "2"}, {"ldc_replay_samples", "4"},
                       {"ldc_session_epochs", "3"}, {"ldc_session_lr", "0.05"}, {"ldc_session_batch", "7"}});
}

// The pretraining a method files with the values its entry declares as read after it changed.
struct StageCase {
  std::string method;
  Values changed;             // every declared value that leaves the stage shared, each changed
  std::set<std::string> own;  // declared values that make the method train its own (above)
};

class ReadAfterPretraining : public ::testing::TestWithParam<StageCase> {};

TEST_P(ReadAfterPretraining, LeavesThePretrainingAsItWas) {
  const StageCase& c = GetParam();
  const MethodEntry& entry = method_entry(c.method);
  std::set<std::string> declared = entry.shared_stages.at(kStage);
  declared.insert(entry.session_only_parameters.begin(), entry.session_only_parameters.end());
  ParameterSet probe;
  create_method(c.method, probe);  // marks the parameters it reads
  std::set<std::string> tested = c.own;
  for (const auto& [key, value] : c.changed) {
    tested.insert(key);
    EXPECT_EQ(probe.used().count(key), 1u) << c.method << " does not read " << key;
  }
  ASSERT_EQ(declared, tested) << "each declared parameter needs a changed value here";

  // All at once, one training per method: any of them moving the pretraining shows.
  KeptStages reference, changed;
  train("pits-sc", kShortBase, &reference);
  Values values = kShortBase;
  for (const auto& [key, value] : c.changed) values[key] = value;
  train(c.method, values, &changed);
  ASSERT_EQ(changed.stages.count(kStage), 1u);
  const TrainedStage& expected = reference.stages.at(kStage);
  const TrainedStage& stage = changed.stages.at(kStage);
  expect_same_state(expected.state, stage.state, c.method + " with every value read after pretraining changed");
  EXPECT_EQ(stage.generator, expected.generator);
  EXPECT_TRUE(torch::equal(stage.torch_random_state, expected.torch_random_state));
  EXPECT_EQ(logged_values(stage.training_log), logged_values(expected.training_log));
}

const Values kPitsAfter = {{"pit_epochs", "2"}, {"pit_lr", "0.02"},   {"pit_episodes", "3"}, {"pit_way", "6"},
                           {"pit_kept", "2"},   {"pit_shot", "2"},    {"pit_query", "3"},    {"pit_alpha", "0.4"},
                           {"epochs_new", "7"}, {"lr_new", "0.37"},   {"lamda_proto", "0.3"}};

INSTANTIATE_TEST_SUITE_P(
    Methods, ReadAfterPretraining,
    ::testing::Values(
        StageCase{"pits-sc", kPitsAfter, {}},
        StageCase{"cop-fscil/cpi",
             with_more(kPitsAfter,
                  {{"cpi_global_bias", "0.5"}, {"cpi_channel_bias", "0.3"}, {"cpi_tilt", "0.4"}, {"cpi_noise", "0.2"},
                   {"cpi_max_shift", "0.3"}, {"cpi_reference", "random"}, {"cpi_distance", "raw"},
                   {"cpi_references", "same"}, {"cpi_mix_alpha", "0.4"}, {"cpi_support_coverage", "0.3"},
                   {"cpi_query_coverage", "0.7"}, {"cpi_kept", "split"}, {"cpi_bn_statistics", "guarded"},
                   {"pcqa_reflections", "3"}, {"pcqa_invariant_fraction", "0.5"}, {"pcqa_sensitive_dim", "3"},
                   {"pcqa_hidden", "5"}, {"pic_weight", "0.5"}, {"pic_probes", "3"}, {"pic_space", "normalised"}, {"pspc_probes", "3"},
                   {"pspc_beta", "2.5"}, {"pspc_q", "own"}, {"pspc_instability", "raw"},
                   {"pspc_mean", "views"}, {"session_loss", "joint"}}),
             {"cpi_space", "cpi_bank", "cpi_pretrain_coverage"}}),
    [](const ::testing::TestParamInfo<StageCase>& info) { return test_name_of(info.param.method); });

}  // namespace
}  // namespace fscil
