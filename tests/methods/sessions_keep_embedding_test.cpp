// What a method's entry declares with MethodEntry::sessions_keep_embedding (the runner then embeds each scored
// sample once per run) holds: embed() gives the same values, to the bit, after two sessions as
// after the base session. A method that does not declare it must change its embedding here, so
// the test would notice a declaration a method could have made but did not, or one it broke.
#include <gtest/gtest.h>

#include <set>

#include "methods/method_registry.h"
#include "core/parameter_set.h"
#include "tests/methods/tiny_base_session.h"

namespace fscil {
namespace {

ParameterSet short_training() {
  ParameterSet params;
  for (const auto& [key, value] : std::map<std::string, std::string>{
           {"pretrain_epochs", "1"}, {"pit_episodes", "2"}, {"pit_epochs", "1"}, {"batch_size", "32"},
           {"orco_base_epochs", "2"}, {"orco_views", "2"}, {"orco_target_steps", "50"},
           {"orco_projector_hidden", "32"}, {"orco_projection_size", "16"}, {"orco_session_epochs", "3"},
           {"orco_session_stop", "last"}, {"pan_pit_episodes", "2"}, {"dsn_session_epochs", "3"}, {"comp_session_steps", "5"},
           {"ldc_calibration_epochs", "2"}, {"ldc_session_epochs", "3"}, {"pa_pct_epochs", "1"},
           {"pa_pct_episodes", "2"}}) {
    params.set(key, value);
  }
  return params;
}

TEST(SessionsKeepEmbedding, HoldsForEveryMethodThatDeclaresItAndOnlyForThose) {
  std::set<std::string> keeping;
  for (const std::string& name : resolve_method_names("all")) {
    torch::manual_seed(5);
    const std::unique_ptr<Method> method = create_method(name, short_training());
    RunContext context = tiny_context(5);
    method->train_base(tiny_base(), context);
    const torch::Tensor samples = torch::randn({7, 2, 4, 4});
    const torch::Tensor before = method->embed(samples);
    method->learn_session(tiny_support(6), context);
    method->learn_session(tiny_support(8), context);
    const bool unchanged = torch::equal(method->embed(samples), before);
    EXPECT_EQ(unchanged, method_entry(name).sessions_keep_embedding) << name;
    if (method_entry(name).sessions_keep_embedding) keeping.insert(name);
  }
  EXPECT_EQ(keeping, (std::set<std::string>{"prototype", "pits-sc", "cop-fscil", "cop-fscil/cpi", "cop-fscil/cpi+pspc",
                                             "cop-fscil/cpi+pcqa", "adbs", "pan", "pa-pct", "dsn", "comp-fscil", "arp", "amfo",
                                             "ldc"}));
}

}  // namespace
}  // namespace fscil
