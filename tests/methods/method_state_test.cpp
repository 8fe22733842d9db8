// Checkpoints at session boundaries: a method restored from save_state() continues exactly.
#include <gtest/gtest.h>

#include "methods/common/stage_progress.h"
#include "methods/common/torch_random_state.h"
#include "methods/method_registry.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet tiny_params() {
  ParameterSet params;
  for (const auto& [key, value] :
       {std::pair{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"pit_epochs", "1"}, {"pit_episodes", "2"},
        {"epochs_new", "5"}, {"orco_base_epochs", "1"}, {"orco_session_epochs", "2"}, {"orco_views", "2"},
        {"orco_target_steps", "20"}, {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"},
        {"orco_session_stop", "last"}, {"pan_pit_episodes", "2"}, {"dsn_session_epochs", "3"}, {"comp_session_steps", "5"},
        {"amfo_session_epochs", "3"}, {"pa_pct_epochs", "1"}, {"pa_pct_episodes", "2"}, {"ldc_calibration_epochs", "3"},
        {"ldc_session_epochs", "3"}}) {
    params.set(key, value);
  }
  return params;
}

class MethodState : public ::testing::TestWithParam<std::string> {};

TEST_P(MethodState, RestoredAfterASessionContinuesExactly) {
  torch::manual_seed(1);
  ParameterSet params = tiny_params();
  auto method = create_method(GetParam(), params);
  RunContext context = tiny_context(1);
  method->train_base(tiny_base(), context);
  method->learn_session(tiny_support(6), context);
  const SessionData next = tiny_support(8);
  const torch::Tensor probe = torch::randn({7, 2, 4, 4});
  const fscil::MethodState state = method->save_state();
  const std::mt19937_64 generator = context.generator;
  const torch::Tensor random_state = torch_random_state();
  method->learn_session(next, context);
  const torch::Tensor expected = method->logits(probe);

  ParameterSet fresh_params = tiny_params();
  auto restored = create_method(GetParam(), fresh_params);
  RunContext fresh = tiny_context(1);
  restored->restore_state(state, fresh);
  fresh.generator = generator;
  restore_torch_random_state(random_state);
  restored->learn_session(next, fresh);
  EXPECT_TRUE(torch::equal(restored->logits(probe), expected)) << GetParam();
  EXPECT_EQ(restored->inference_cost(fresh.input).parameters(), method->inference_cost(context.input).parameters());
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, MethodState,
                         ::testing::Values("prototype", "pits-sc", "cop-fscil/cpi", "cop-fscil", "orco", "adbs", "pan", "pa-pct", "dsn",
                                           "comp-fscil", "arp", "amfo", "ldc"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

TEST(MethodStateFit, AStateOfAnotherMethodIsRefused) {
  torch::manual_seed(1);
  ParameterSet params = tiny_params();
  auto pits = create_method("pits-sc", params);
  RunContext context = tiny_context(1);
  pits->train_base(tiny_base(), context);
  ParameterSet other_params = tiny_params();
  auto cop = create_method("cop-fscil", other_params);
  RunContext other = tiny_context(1);
  try {
    cop->restore_state(pits->save_state(), other);
    FAIL() << "expected MethodError";
  } catch (const MethodError& error) {
    EXPECT_NE(std::string(error.what()).find("state has no 'adapter."), std::string::npos) << error.what();
  }
}

// A stage continued by another process (stage_progress.h) takes its optimiser's momentum back: the
// next Nesterov step is then the one the first optimiser would have taken, to the bit.
TEST(StageProgress, MomentumTakenBackGivesTheSameNextStep) {
  torch::manual_seed(3);
  const torch::Tensor start = torch::randn({4, 3});
  const auto step = [](torch::optim::SGD& optimizer, const torch::Tensor& weight) {
    optimizer.zero_grad();
    (weight * weight).sum().backward();
    optimizer.step();
  };
  const auto sgd = [](const torch::Tensor& weight) {
    return torch::optim::SGD({weight}, torch::optim::SGDOptions(0.1).momentum(0.9).nesterov(true));
  };
  torch::Tensor weight = start.clone().requires_grad_(true);
  torch::optim::SGD first = sgd(weight);
  step(first, weight);
  step(first, weight);
  fscil::MethodState state;
  put_momentum(state, "m.", first);
  ASSERT_EQ(state.size(), 1u);
  torch::Tensor continued = weight.detach().clone().requires_grad_(true);
  torch::Tensor fresh = weight.detach().clone().requires_grad_(true);
  torch::optim::SGD second = sgd(continued);
  take_momentum(state, "m.", second);
  torch::optim::SGD without = sgd(fresh);
  step(first, weight);
  step(second, continued);
  step(without, fresh);
  EXPECT_TRUE(torch::equal(weight, continued));
  EXPECT_FALSE(torch::equal(weight, fresh)) << "a step without the momentum differs: the test can fail";

  state["m.0"] = torch::zeros({2});
  torch::optim::SGD misfit = sgd(continued);
  EXPECT_THROW(take_momentum(state, "m.", misfit), MethodError);
}

}  // namespace
}  // namespace fscil
