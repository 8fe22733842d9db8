#include "core/stable_hash.h"

#include <fmt/format.h>

#include <cstdint>

namespace fscil {

std::string stable_hash(const std::string& text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return fmt::format("{:016x}", hash);
}

std::string stable_hash(const std::map<std::string, std::string>& values) {
  std::string text;
  for (const auto& [key, value] : values) text += key + "=" + value + ";";
  return stable_hash(text);
}

}  // namespace fscil
