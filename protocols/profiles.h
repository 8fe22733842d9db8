#pragma once
#include <string>
#include <vector>

namespace fscil {

class ParameterSet;

// A schedule length. What it changes in a method's schedule is the method's registry entry's to
// say (MethodEntry::profile_defaults); the profile only names and describes itself.
struct Profile {
  const char* name;
  const char* summary;
};

const std::vector<Profile>& profiles();
// Applies every registered method's defaults for the named profile (before --set); throws
// ProtocolError for an unknown name, MethodError where two methods shorten one key differently.
// Throws ProtocolError unless `name` is a profile; `where` (a file) starts the message.
void require_profile(const std::string& name, const std::string& where = "");
void apply_profile(const std::string& name, ParameterSet& params);

}  // namespace fscil
