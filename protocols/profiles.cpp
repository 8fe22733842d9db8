#include "protocols/profiles.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "core/error.h"
#include "core/shown_text.h"
#include "core/parameter_set.h"
#include "methods/method_registry.h"

namespace fscil {

// The paper's schedule is every method's default; how fast and smoke shorten a method's schedule
// is the method's to say (MethodEntry::profile_defaults).
const std::vector<Profile>& profiles() {
  // The smoke profile times inference over one pass (after the warm-up): its runs are the test
  // suite's, whose IT nobody reads, and seven passes were about 0.9 s of a 5-13 s run (ours).
  static const std::vector<Profile> table = {
      {"smoke", "whole protocol in seconds per method (tests; inference timed over one pass); use with simtex-mini", 1},
      {"fast", "default: base stages until their base validation converges (6-40 epochs, lr halved every 4; "
               "pseudo-incremental stages at most their released length); measured: the README's main job, 13 "
               "methods then, 36 min 47 s on a 2-core AMD EPYC Zen 4 (docs/profiling.md); `plan` estimates yours",
       kTimedInferenceRepeats},
      {"paper", "the paper's schedule (100/10/200 epochs of pretraining, pseudo-incremental training and "
       "session fine-tuning; lr halved every 40)", kTimedInferenceRepeats},
  };
  return table;
}

const Profile& require_profile(const std::string& name, const std::string& where) {
  const auto found = std::find_if(profiles().begin(), profiles().end(), [&](const Profile& p) { return name == p.name; });
  if (found == profiles().end()) {
    std::vector<std::string> names;
    for (const auto& profile : profiles()) names.emplace_back(profile.name);
    throw ProtocolError(fmt::format("{}unknown profile '{}': expected one of {}", where.empty() ? "" : where + ": ",
                                    shown_text(name), fmt::join(names, ", ")));
  }
  return *found;
}

void apply_profile(const std::string& name, ParameterSet& params) {
  require_profile(name);
  // Every method's defaults for the profile: methods sharing a stage share its keys, and must agree.
  std::map<std::string, std::pair<std::string, std::string>> applied;  // key -> value, method
  for (const auto& entry : method_registry()) {
    const auto defaults = entry.profile_defaults.find(name);
    if (defaults == entry.profile_defaults.end()) continue;
    for (const auto& [key, value] : defaults->second) {
      const auto [earlier, first] = applied.emplace(key, std::make_pair(value, entry.name));
      if (!first && earlier->second.first != value) {
        throw MethodError(fmt::format("profile {}: {} sets {}={} where {} sets {}", name, entry.name, key, value,
                                      earlier->second.second, earlier->second.first));
      }
      params.set_default(key, value);
    }
  }
}

}  // namespace fscil
