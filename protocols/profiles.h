#pragma once
#include <string>
#include <vector>

namespace fscil {

class ParameterSet;

// Timed passes of a run's inference time where the profile does not say fewer.
constexpr int kTimedInferenceRepeats = 7;

// A schedule length. What it changes in a method's schedule is the method's registry entry's to
// say (MethodEntry::profile_defaults); the profile names and describes itself, and says how many
// timed passes measure a run's inference time (protocols/protocol_runner.h, time_inference).
struct Profile {
  const char* name;
  const char* summary;
  int timed_inference_passes;
};

const std::vector<Profile>& profiles();
// The named profile; throws ProtocolError unless `name` is a profile (`where`, a file, starts the message).
const Profile& require_profile(const std::string& name, const std::string& where = "");
// Applies every registered method's defaults for the named profile (before --set); throws
// ProtocolError for an unknown name, MethodError where two methods shorten one key differently.
void apply_profile(const std::string& name, ParameterSet& params);

}  // namespace fscil
