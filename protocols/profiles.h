#pragma once
#include <string>
#include <vector>

namespace fscil {

class ParameterSet;

struct Profile {
  const char* name;
  const char* summary;
  // key=value defaults the profile applies before --set; they only shorten schedules.
  std::vector<std::pair<const char*, const char*>> settings;
};

const std::vector<Profile>& profiles();
// Applies the named profile's settings; throws ProtocolError for an unknown name.
void apply_profile(const std::string& name, ParameterSet& params);

// The released per-dataset hyper-parameters (PITS-SC's LS-100 and NS-100 configs: epochs,
// learning rates, CutMix probability, mixing alpha). Applied before the profile, which may
// shorten the epochs, and before --set. Datasets without an entry keep the tactile defaults.
void apply_dataset_defaults(const std::string& dataset, ParameterSet& params);

}  // namespace fscil
