#pragma once
#include <string>

namespace fscil {

// Plain text as LaTeX text: dataset names may hold '_' (a folder-format dataset such as lab_2024),
// which LaTeX would read as a subscript outside math mode, and a method's note in a result file is
// free text: no character of it may act as a command.
inline std::string latex_text(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (c == '\\') {
      out += "\\textbackslash{}";
    } else if (c == '~') {
      out += "\\textasciitilde{}";
    } else if (c == '^') {
      out += "\\textasciicircum{}";
    } else {
      if (c == '_' || c == '&' || c == '%' || c == '#' || c == '$' || c == '{' || c == '}') out += '\\';
      out += c;
    }
  }
  return out;
}

}  // namespace fscil
