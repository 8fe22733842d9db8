#include "protocols/profiles.h"

#include <fmt/format.h>

#include "core/parameter_set.h"
#include "core/protocol_error.h"

namespace fscil {

// The paper's schedule is every method's default; fast and smoke shrink the epochs (and the
// learning-rate step with them, so the decay still happens) and nothing else.
const std::vector<Profile>& profiles() {
  static const std::vector<Profile> table = {
      {"smoke", "whole protocol in seconds per method (tests); use with simtex-mini",
       {{"pretrain_epochs", "3"}, {"lr_step", "2"}, {"pit_epochs", "1"}, {"pit_episodes", "4"}, {"epochs_new", "20"}}},
      {"fast", "default: every method of the main README job within 20 minutes on 2 cores",
       {{"pretrain_epochs", "8"}, {"lr_step", "4"}, {"pit_epochs", "2"}}},
      {"paper", "the paper's schedule (100/10/200 epochs of pretraining, pseudo-incremental training and "
       "session fine-tuning; lr halved every 40)", {}},
  };
  return table;
}

void apply_profile(const std::string& name, ParameterSet& params) {
  for (const auto& profile : profiles()) {
    if (name != profile.name) continue;
    for (const auto& [key, value] : profile.settings) params.set_default(key, value);
    return;
  }
  std::vector<std::string> names;
  for (const auto& profile : profiles()) names.emplace_back(profile.name);
  throw ProtocolError(fmt::format("unknown profile '{}': expected one of {}", name, fmt::join(names, ", ")));
}

}  // namespace fscil
