#pragma once
#include <map>
#include <string>

namespace fscil {

// 64-bit FNV-1a of a canonical parameter text, as 16 hex digits.
std::string stable_hash(const std::string& text);
// stable_hash of "key=value;" for every entry, in key order: named values (parameters, library
// versions) as one digest.
std::string stable_hash(const std::map<std::string, std::string>& values);

}  // namespace fscil
