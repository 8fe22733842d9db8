#pragma once
#include <cstddef>
#include <string>

namespace fscil {

// Whether the JSON `text` opens more than `depth` arrays and objects inside one another (strings
// skipped). Checked before parsing: the library's copies and messages recurse once per level, so
// a few hundred kilobytes of brackets would overflow the stack; no file fscil-bench reads nests
// more than a handful of levels.
inline bool json_nests_deeper_than(const std::string& text, int depth) {
  int open = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;  // the escaped character cannot end the string
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++open > depth) return true;
    } else if ((c == ']' || c == '}') && open > 0) {
      --open;
    }
  }
  return false;
}

inline constexpr int kDeepestJson = 64;

}  // namespace fscil
