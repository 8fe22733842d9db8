#pragma once
#include <string>

namespace fscil {

// A name as LaTeX text: dataset names may hold '_' (a folder-format dataset such as lab_2024),
// which LaTeX would read as a subscript outside math mode.
inline std::string latex_text(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (c == '_' || c == '&' || c == '%' || c == '#' || c == '$') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace fscil
