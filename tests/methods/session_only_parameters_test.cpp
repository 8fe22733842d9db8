// What a method declares as read only after the base session (MethodEntry::session_only_parameters,
// left out of a base's stage-cache identity) really leaves the base untouched: a base trained
// with each such value changed ends in the same state, to the bit, with the same random state.
#include <gtest/gtest.h>

#include <map>

#include "methods/common/torch_random_state.h"
#include "methods/method_registry.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_training.h"

namespace fscil {
namespace {

using Values = std::map<std::string, std::string>;

struct BaseOutcome {
  MethodState state;
  std::mt19937_64 generator;
  torch::Tensor torch_state;
};

BaseOutcome train_base(const std::string& method_name, const Values& values,
                       EpochSelection selection = EpochSelection::last) {
  const std::unique_ptr<Method> method = tiny_method(method_name, values);
  RunContext context = tiny_context(5);
  // Scored data for either selection: the base itself stands in for validation and test.
  const SessionData scored = tiny_base();
  context.validation = &scored;
  context.oracle_test = &scored;
  context.selection = selection;
  method->train_base(tiny_base(), context);
  return {method->save_state(), context.generator, torch_random_state()};
}

void expect_same_base(const BaseOutcome& expected, const BaseOutcome& actual, const std::string& what) {
  expect_same_state(expected.state, actual.state, what);
  EXPECT_EQ(actual.generator, expected.generator) << what;
  EXPECT_TRUE(torch::equal(actual.torch_state, expected.torch_state)) << what;
}

struct SessionOnlyCase {
  std::string method;
  Values base;     // a short base training
  Values changed;  // every session-only parameter, each with a value other than its default
};

class SessionOnlyParameters : public ::testing::TestWithParam<SessionOnlyCase> {};

TEST_P(SessionOnlyParameters, LeaveTheBaseSessionAsItWas) {
  const SessionOnlyCase& c = GetParam();
  ParameterSet probe;
  for (const auto& [key, value] : c.base) probe.set(key, value);
  create_method(c.method, probe);  // marks the parameters it reads
  const std::set<std::string>& declared = method_entry(c.method).session_only_parameters;
  std::set<std::string> tested;
  for (const auto& [key, value] : c.changed) {
    tested.insert(key);
    EXPECT_EQ(probe.used().count(key), 1u) << c.method << " does not read " << key;
  }
  ASSERT_EQ(declared, tested) << "each declared parameter needs a changed value here";

  const BaseOutcome reference = train_base(c.method, c.base);
  for (const auto& [key, value] : c.changed) {
    Values values = c.base;
    values[key] = value;
    expect_same_base(reference, train_base(c.method, values), c.method + " " + key + "=" + value);
  }
}

const Values kPitsBase = {{"pretrain_epochs", "1"}, {"pit_episodes", "2"}, {"pit_epochs", "1"}, {"batch_size", "32"}};
const Values kPitsSession = {{"epochs_new", "7"}, {"lr_new", "0.37"}, {"lamda_proto", "0.3"}};

INSTANTIATE_TEST_SUITE_P(
    Methods, SessionOnlyParameters,
    ::testing::Values(
        SessionOnlyCase{"pits-sc", kPitsBase, kPitsSession},
        SessionOnlyCase{"cop-fscil", kPitsBase,
             with_more(kPitsSession, {{"pspc_probes", "3"}, {"pspc_beta", "2.5"}, {"pspc_q", "own"},
                                 {"pspc_instability", "raw"}, {"pspc_mean", "views"}, {"session_loss", "joint"}})},
        SessionOnlyCase{"orco",
             {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"orco_base_epochs", "2"}, {"orco_views", "2"},
              {"orco_target_steps", "50"}, {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"},
              {"orco_session_stop", "last"}},
             {{"orco_session_epochs", "3"}, {"orco_session_lr", "0.02"}, {"orco_session_batch", "16"},
              {"orco_session_warmup", "2"}, {"orco_session_stop", "validation"}, {"orco_session_check", "2"},
              {"orco_session_patience", "4"}, {"orco_novel_ce_weight", "0.9"}, {"orco_base_ce_weight", "0.1"},
              {"orco_session_orthogonality", "all"}}},
        SessionOnlyCase{"adbs", {{"pretrain_epochs", "1"}, {"batch_size", "32"}},
             {{"adbs_session_steps", "3"}, {"adbs_session_lr", "0.05"}}},
        SessionOnlyCase{"pan", {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"pan_pit_episodes", "2"}},
             {{"pan_session_steps", "3"}, {"pan_session_lr", "0.05"}}},
        SessionOnlyCase{"pa-pct",
             {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"pan_pit_episodes", "2"}, {"pa_pct_epochs", "1"},
              {"pa_pct_episodes", "2"}},
             {{"pan_session_steps", "3"}, {"pan_session_lr", "0.05"}, {"pa_pct_session_lr", "0.001"}}},
        SessionOnlyCase{"dsn", {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"dsn_session_epochs", "3"}},
             {{"dsn_gamma", "0.5"}, {"dsn_session_epochs", "2"}, {"dsn_session_lr", "0.05"}, {"dsn_session_batch", "64"},
              {"dsn_refresh_every", "1"}, {"dsn_new_samples", "3"}, {"dsn_old_samples", "3"}, {"dsn_base_samples", "3"},
              {"dsn_sample_k", "2"}, {"dsn_top_k", "1"}}},
        SessionOnlyCase{"comp-fscil", {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"comp_session_steps", "3"}},
             {{"comp_session_steps", "2"}, {"comp_session_lr", "0.05"}}},
        SessionOnlyCase{"amfo", {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"amfo_session_epochs", "3"}},
             {{"amfo_session_fusion_weight", "5"}, {"amfo_session_margin_weight", "1"}, {"amfo_session_binary_weight", "0.2"},
              {"amfo_gamma", "0.5"}, {"amfo_r", "0.1"}, {"amfo_session_epochs", "2"}, {"amfo_session_lr", "0.05"},
              {"amfo_session_batch", "64"}, {"amfo_refresh_every", "1"}, {"amfo_new_samples", "3"},
              {"amfo_old_samples", "3"}}},
        SessionOnlyCase{"ldc", {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"ldc_calibration_epochs", "2"}},
             {{"ldc_session_epochs", "2"}, {"ldc_session_lr", "0.05"}, {"ldc_session_batch", "7"}}}),
    [](const ::testing::TestParamInfo<SessionOnlyCase>& info) { return test_name_of(info.param.method); });

// Every method whose entry says base_ignores_selection ends its base in the same state under every
// selection (the stage cache shares it).
TEST(BaseIgnoresSelection, HoldsForEveryMethodThatSaysSo) {
  const std::map<std::string, Values> short_bases = {
      {"orco",
       {{"pretrain_epochs", "1"}, {"batch_size", "32"}, {"orco_base_epochs", "2"}, {"orco_views", "2"},
        {"orco_target_steps", "50"}, {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"}}}};
  for (const auto& entry : method_registry()) {
    if (!entry.base_ignores_selection) continue;
    ASSERT_EQ(short_bases.count(entry.name), 1u) << entry.name << " needs a short base here";
    const BaseOutcome last = train_base(entry.name, short_bases.at(entry.name));
    for (const EpochSelection selection : {EpochSelection::validation, EpochSelection::test_oracle}) {
      expect_same_base(last, train_base(entry.name, short_bases.at(entry.name), selection), entry.name);
    }
  }
}

}  // namespace
}  // namespace fscil
