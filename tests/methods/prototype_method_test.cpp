#include "methods/prototype/prototype_method.h"

#include <gtest/gtest.h>

#include <csignal>
#include <functional>
#include <memory>
#include <sstream>

#include "core/stop_request.h"
#include "datasets/dataset_catalog.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/supervised_training.h"
#include "methods/method_registry.h"
#include "protocols/profiles.h"
#include "protocols/protocol_runner.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

TEST(ResNet18Encoder, EmbedsBothTactileShapesIntoTwoHundredFiftySixDimensions) {
  torch::manual_seed(0);
  ResNet18Encoder haptex(ResNet18Options{5, 64});
  haptex->eval();
  EXPECT_EQ(haptex->forward(torch::randn({3, 5, 64, 24})).sizes(), (std::vector<std::int64_t>{3, 256}));
  ResNet18Encoder lmt(ResNet18Options{3, 64});
  lmt->eval();
  EXPECT_EQ(lmt->forward(torch::randn({2, 3, 64, 493})).sizes(), (std::vector<std::int64_t>{2, 256}));
  // bn0 normalises the 64 Mel bins: 64 weights and 64 biases among the parameters.
  const auto named = haptex->named_parameters();
  EXPECT_EQ(named["bn0.weight"].numel(), 64);
  // Stem 7x7 over 5 input channels into 64.
  EXPECT_EQ(named["conv1.weight"].sizes(), (std::vector<std::int64_t>{64, 5, 7, 7}));
}

TEST(CosineClassifier, ScoresTemperatureTimesCosineOverSeenRowsOnly) {
  CosineClassifier classifier(4, 2, 16.0);
  classifier->set_rows(0, torch::tensor({{1.0f, 0.0f}, {0.0f, 2.0f}, {1.0f, 1.0f}, {-1.0f, 0.0f}}));
  const torch::Tensor logits = classifier->forward(torch::tensor({{3.0f, 4.0f}}), 3);
  ASSERT_EQ(logits.sizes(), (std::vector<std::int64_t>{1, 3}));
  EXPECT_NEAR(logits[0][0].item<float>(), 16.0 * 0.6, 1e-5);
  EXPECT_NEAR(logits[0][1].item<float>(), 16.0 * 0.8, 1e-5);
  EXPECT_NEAR(logits[0][2].item<float>(), 16.0 * 7.0 / (5.0 * std::sqrt(2.0)), 1e-5);
}

class PrototypeOnSimtexMini : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::stringstream log;
    dataset_ = new PreparedDataset(prepare_dataset("simtex-mini", DatasetRequest{}, ParameterSet(), log));
  }
  static void TearDownTestSuite() { delete dataset_; }

  // `protocol` holds protocol keys (removal=fciac); `wrap` may put a test method around prototype's.
  std::vector<SessionOutcome> run(std::uint64_t seed, const ParameterSet& protocol = ParameterSet(),
                                  const std::function<std::unique_ptr<Method>(std::unique_ptr<Method>)>& wrap = {}) {
    ParameterSet params = protocol;
    apply_profile("smoke", params);
    const SessionPlan plan = make_session_plan(20, dataset_->description.sessions, params, seed);
    const SessionSchedule schedule = build_session_schedule(dataset_->segments, dataset_->description.class_names, plan,
                                                            SplitMode::recording, seed);
    auto method = create_method("prototype", params);
    if (wrap) method = wrap(std::move(method));
    torch::manual_seed(seed);
    RunContext context;
    context.seed = seed;
    context.generator = std::mt19937_64(seed);
    return run_sessions(*method, *dataset_, schedule, context);
  }

  static PreparedDataset* dataset_;
};
PreparedDataset* PrototypeOnSimtexMini::dataset_ = nullptr;

TEST_F(PrototypeOnSimtexMini, LearnsFarAboveChanceAndRepeatsExactlyWithTheSameSeed) {
  const auto first = run(1);
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(first[0].seen_classes, 10);
  EXPECT_EQ(first[2].seen_classes, 20);
  EXPECT_EQ(first[0].accuracy.samples, 10 * 5);  // 1 of 6 recordings x 5 segments per class
  EXPECT_EQ(first[2].accuracy.samples, 20 * 5);
  // Chance is 10% after the base session and 5% after the last.
  EXPECT_GT(first[0].accuracy.all, 30.0);
  EXPECT_GT(first[2].accuracy.novel, 15.0);
  // The base session scores base rows only, so no base sample can go to a novel class; later, the
  // errors that cross groups are a part of each group's errors.
  EXPECT_EQ(first[0].diagnostics.at("scored_base_as_novel"), 0.0);
  EXPECT_EQ(first[0].diagnostics.count("scored_novel_as_base"), 0u);
  EXPECT_LE(first[2].diagnostics.at("scored_base_as_novel"), 100.0 - first[2].accuracy.base + 1e-9);
  EXPECT_LE(first[2].diagnostics.at("scored_novel_as_base"), 100.0 - first[2].accuracy.novel + 1e-9);
  EXPECT_GT(first[2].diagnostics.at("scored_base_as_novel") + first[2].diagnostics.at("scored_novel_as_base"), 0.0);
  const auto again = run(1);
  for (std::size_t s = 0; s < first.size(); ++s) EXPECT_EQ(first[s].accuracy.all, again[s].accuracy.all);
}

// What the runner asked of a method: the sessions it learned and the classes it was told to forget.
struct MethodCalls {
  std::vector<int> learned;
  std::vector<std::vector<std::int64_t>> forgotten;
};

// Prototype's method, with one row that wins every decision it takes part in.
class FavouringOneRow : public Method {
 public:
  FavouringOneRow(std::unique_ptr<Method> inner, int favoured, MethodCalls& calls)
      : inner_(std::move(inner)), favoured_(favoured), calls_(calls) {}
  void train_base(const SessionData& base, RunContext& context) override { inner_->train_base(base, context); }
  void learn_session(const SessionData& support, RunContext& context) override {
    calls_.learned.push_back(support.session);
    inner_->learn_session(support, context);
  }
  void forget_classes(const std::vector<std::int64_t>& classes, RunContext&) override {
    calls_.forgotten.push_back(classes);
  }
  torch::Tensor embed(const torch::Tensor& features) override { return inner_->embed(features); }
  torch::Tensor classify(const torch::Tensor& embeddings) override {
    torch::Tensor logits = inner_->classify(embeddings);
    if (logits.size(1) > favoured_) logits.select(1, favoured_).add_(1000);
    return logits;
  }
  MethodState save_state() const override { return inner_->save_state(); }
  void restore_state(const MethodState& state, RunContext& context) override { inner_->restore_state(state, context); }
  ModelCost inference_cost(const InputShape& input) const override { return inner_->inference_cost(input); }


 private:
  std::unique_ptr<Method> inner_;
  int favoured_;
  MethodCalls& calls_;
};

// Issue 71: simtex-mini's 3 sessions under removal=fciac: session 1 adds classes 10-14, session 2
// removes base class 9 and novel class 14. A removed class's samples are no longer scored, and
// its row takes part in no decision, whatever the method's logits say.
TEST_F(PrototypeOnSimtexMini, TheClassVariableProtocolScoresThePresentClassesOverTheirRowsOnly) {
  ParameterSet protocol;
  protocol.set("removal", "fciac");
  MethodCalls calls;
  const auto outcomes = run(1, protocol, [&](std::unique_ptr<Method> inner) {
    return std::unique_ptr<Method>(std::make_unique<FavouringOneRow>(std::move(inner), 14, calls));
  });
  ASSERT_EQ(outcomes.size(), 3u);
  EXPECT_EQ(calls.learned, (std::vector<int>{1})) << "a removing session trains nothing";
  ASSERT_EQ(calls.forgotten.size(), 1u);
  EXPECT_EQ(calls.forgotten[0], (std::vector<std::int64_t>{9, 14}));
  EXPECT_EQ(outcomes[1].seen_classes, 15);
  EXPECT_EQ(outcomes[2].seen_classes, 13) << "the classes scored";
  EXPECT_EQ(outcomes[1].accuracy.samples, 15 * 5);
  EXPECT_EQ(outcomes[2].accuracy.samples, 13 * 5);
  // In session 1 row 14 is a class of its own and takes every sample: only its 5 are right.
  EXPECT_NEAR(outcomes[1].accuracy.all, 100.0 * 5 / 75, 1e-9);
  // Removed, it wins nothing (had it, every sample would be wrong): the session scores prototype's
  // own decisions among the 13 classes, far above their chance of 7.7%.
  EXPECT_GT(outcomes[2].accuracy.all, 30.0);
  EXPECT_NEAR(outcomes[0].accuracy.all, run(1)[0].accuracy.all, 1e-9);
  EXPECT_EQ(outcomes[2].accuracy.current, 0.0) << "a removing session introduces no class";
}

TEST(MethodRegistry, ResolvesAllAndRejectsUnknownNames) {
  EXPECT_EQ(resolve_method_names("all").front(), "prototype");
  EXPECT_EQ(resolve_method_names("prototype"), (std::vector<std::string>{"prototype"}));
  EXPECT_THROW(resolve_method_names("prototype,nosuch"), MethodError);
  EXPECT_THROW(create_method("nosuch", ParameterSet()), MethodError);
}

// On more threads than cores one epoch can take minutes: SIGTERM must not wait for its end.
TEST(SupervisedTraining, AStopAskedDuringAnEpochIsHonouredAfterTheStepNotAtTheEpochsEnd) {
  const SessionData base = tiny_base();  // 150 samples: 15 batches of 10
  RunContext context = tiny_context(1);
  const torch::Tensor weight = torch::zeros({1}, torch::requires_grad());
  SupervisedSchedule schedule;
  schedule.epochs = 1;
  schedule.batch_size = 10;
  int batches = 0;
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor&) {
    if (++batches == 2) std::raise(SIGTERM);
    return (weight * features.mean()).sum();
  };
  install_stop_handlers();
  EXPECT_THROW(train_epochs({weight}, loss, base, schedule, context, "pretraining"), StopRequested);
  clear_stop_request();
  std::signal(SIGTERM, SIG_DFL);
  EXPECT_EQ(batches, 2);
  EXPECT_TRUE(context.training_log.empty());  // the epoch never finished
}

}  // namespace
}  // namespace fscil
