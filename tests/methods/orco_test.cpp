// OrCo as a method on the tiny 10-class protocol (6 base, 2-way 5-shot): the projector reset,
// the replay memory's exact content and size, the target assignment and seeded repeatability.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "methods/method_registry.h"
#include "methods/orco/orco_method.h"
#include "core/parameter_set.h"
#include "core/error.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet tiny_params(int session_epochs) {
  ParameterSet params;
  for (const auto& [key, value] : {std::pair{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"orco_base_epochs", "2"},
                                   {"orco_views", "2"}, {"orco_target_steps", "50"}, {"orco_projector_hidden", "32"},
                                   {"orco_projection_size", "16"}}) {
    params.set(key, value);
  }
  params.set("orco_session_epochs", std::to_string(session_epochs));
  params.set("orco_session_stop", "last");  // the tiny context has no validation split
  return params;
}

struct TrainedOrco {
  std::unique_ptr<Method> method;
  RunContext context;
  OrcoMethod& orco() { return dynamic_cast<OrcoMethod&>(*method); }
};

using Settings = std::vector<std::pair<std::string, std::string>>;

TrainedOrco train(int session_epochs, std::uint64_t seed = 3, const Settings& settings = {}) {
  torch::manual_seed(seed);
  ParameterSet params = tiny_params(session_epochs);
  for (const auto& [key, value] : settings) params.set(key, value);
  TrainedOrco trained{create_method("orco", params), tiny_context(seed)};
  trained.method->train_base(tiny_base(), trained.context);
  return trained;
}

TEST(Orco, SessionsStartFromTheProjectorOfPhaseTwo) {
  TrainedOrco trained = train(/*session_epochs=*/3);
  OrcoMethod& orco = trained.orco();
  EXPECT_TRUE(orco.phase_two_projector().matches(*orco.projector()));
  trained.method->learn_session(tiny_support(6), trained.context);
  EXPECT_FALSE(orco.phase_two_projector().matches(*orco.projector())) << "a session trains the projector";

  // With no session epochs the projector after a session is exactly the phase-2 one, however
  // far it had moved before: the reset restores every weight.
  TrainedOrco resetting = train(/*session_epochs=*/0);
  OrcoMethod& reset = resetting.orco();
  {
    torch::NoGradGuard no_grad;
    for (auto& parameter : reset.projector()->parameters()) parameter.add_(1.0);
  }
  EXPECT_FALSE(reset.phase_two_projector().matches(*reset.projector()));
  resetting.method->learn_session(tiny_support(6), resetting.context);
  EXPECT_TRUE(reset.phase_two_projector().matches(*reset.projector()));
}

TEST(Orco, ReplayMemoryHoldsTheFirstFiveOfEachBaseClassThenEveryShot) {
  TrainedOrco trained = train(/*session_epochs=*/1, 3, {{"orco_exemplars_from", "first"}});
  const ReplayMemory& memory = trained.orco().replay_memory();
  ASSERT_EQ(memory.samples(), 6 * 5);
  // tiny_base lists 25 samples per class in class order: the first five are rows 25c .. 25c+4.
  torch::manual_seed(3);
  const SessionData same_base = tiny_base();  // the features train() saw (same torch seed)
  for (std::int64_t c = 0; c < 6; ++c) {
    EXPECT_TRUE(torch::equal(memory.features().slice(0, 5 * c, 5 * c + 5), same_base.features.all().slice(0, 25 * c, 25 * c + 5)))
        << "class " << c;
    EXPECT_TRUE(torch::all(memory.labels().slice(0, 5 * c, 5 * c + 5) == c).item<bool>());
  }
  const std::int64_t bytes_per_sample = 2 * 4 * 4 * static_cast<std::int64_t>(sizeof(float));
  EXPECT_EQ(memory.bytes(), 30 * bytes_per_sample);

  const SessionData first = tiny_support(6), second = tiny_support(8);
  trained.method->learn_session(first, trained.context);
  trained.method->learn_session(second, trained.context);
  EXPECT_EQ(memory.samples(), 30 + 10 + 10);
  EXPECT_TRUE(torch::equal(memory.features().slice(0, 30, 40), first.features.all()));
  EXPECT_TRUE(torch::equal(memory.features().slice(0, 40, 50), second.features.all()));
  const ReplayFootprint footprint = trained.method->replay_footprint();
  EXPECT_EQ(footprint.samples, 50);
  EXPECT_EQ(footprint.bytes, 50 * bytes_per_sample);
}

TEST(Orco, EverySeenClassOwnsItsOwnTargetAndIsScoredByCosineToIt) {
  TrainedOrco trained = train(/*session_epochs=*/1);
  trained.method->learn_session(tiny_support(6), trained.context);
  OrcoMethod& orco = trained.orco();
  const auto& owned = orco.class_targets();
  ASSERT_EQ(owned.size(), 8u);
  EXPECT_EQ(std::set<std::int64_t>(owned.begin(), owned.end()).size(), 8u);
  torch::manual_seed(11);
  const torch::Tensor probe = torch::randn({4, 2, 4, 4});
  const torch::Tensor embeddings = trained.method->embed(probe);
  EXPECT_TRUE(torch::allclose(embeddings.norm(2, 1), torch::ones({4}), 0, 1e-5));
  const torch::Tensor logits = trained.method->classify(embeddings);
  ASSERT_EQ(logits.sizes(), (std::vector<std::int64_t>{4, 8}));
  for (std::int64_t c = 0; c < 8; ++c) {
    const torch::Tensor cosine = embeddings.matmul(orco.targets()[owned[static_cast<std::size_t>(c)]]);
    EXPECT_TRUE(torch::allclose(logits.select(1, c), cosine, 0, 1e-5));
  }
}

TEST(Orco, SameSeedRepeatsExactly) {
  torch::Tensor logits[2];
  for (auto& result : logits) {
    TrainedOrco trained = train(/*session_epochs=*/2, /*seed=*/7);
    trained.method->learn_session(tiny_support(6), trained.context);
    torch::manual_seed(5);
    result = trained.method->logits(torch::randn({6, 2, 4, 4}));
  }
  EXPECT_TRUE(torch::equal(logits[0], logits[1]));
}

// With the validation stop, the projector a session ends with is the one whose harmonic mean
// of base-validation and own-shot accuracy was best at a check; checks follow epochs 1, 3, 5, ...
// (the first after one epoch, as the reference's); patience 1 stops at the first check that is
// not better.
TEST(Orco, SessionKeepsTheProjectorOfItsBestValidationCheck) {
  const Settings stop = {{"orco_session_stop", "validation"}, {"orco_session_check", "2"}, {"orco_session_patience", "1"}};
  TrainedOrco trained = train(/*session_epochs=*/30, 3, stop);
  torch::manual_seed(12);
  const SessionData validation = tiny_base();  // six base classes, like the base validation split
  trained.context.validation = &validation;
  const SessionData shots = tiny_support(6);
  trained.method->learn_session(shots, trained.context);

  const auto& diagnostics = trained.context.diagnostics;
  ASSERT_EQ(diagnostics.count("session_stop_score"), 1u);
  const double trained_epochs = diagnostics.at("session_epochs_trained"), kept = diagnostics.at("session_kept_epoch");
  EXPECT_EQ(static_cast<int>(kept) % 2, 1);
  EXPECT_LE(kept, trained_epochs);
  EXPECT_EQ(trained_epochs, std::min(30.0, kept + 2)) << "stops at the first check after the best";
  const auto accuracy = [&](const SessionData& data) {
    const torch::Tensor predicted = trained.method->logits(data.features.all()).argmax(1);
    return 100.0 * predicted.eq(data.labels).to(torch::kDouble).mean().item<double>();
  };
  const double base = accuracy(validation), novel = accuracy(shots);
  EXPECT_NEAR(diagnostics.at("session_stop_score"), 2 * base * novel / (base + novel), 1e-9);

  // Without a validation split the stop cannot be computed: one clear error.
  TrainedOrco blind = train(/*session_epochs=*/2, 3, stop);
  EXPECT_THROW(blind.method->learn_session(tiny_support(6), blind.context), MethodError);
}

TEST(Orco, IsRegisteredAndPartOfAll) {
  const auto all = resolve_method_names("all");
  EXPECT_NE(std::find(all.begin(), all.end(), "orco"), all.end());
  EXPECT_EQ(resolve_method_names("orco"), std::vector<std::string>{"orco"});
}

TEST(Orco, RefusesBadSettingsBeforeTraining) {
  ParameterSet one_view = tiny_params(1);
  one_view.set("orco_views", "1");
  EXPECT_THROW(create_method("orco", one_view), ProtocolError);
  ParameterSet negative = tiny_params(1);
  negative.set("orco_session_lr", "-0.1");
  EXPECT_THROW(create_method("orco", negative), ProtocolError);
}

}  // namespace
}  // namespace fscil
