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


}  // namespace fscil
