#pragma once
#include <string>

namespace fscil {

// 64-bit FNV-1a of a canonical parameter text, as 16 hex digits.
std::string stable_hash(const std::string& text);

}  // namespace fscil
