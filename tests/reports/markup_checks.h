#pragma once
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

namespace fscil {

// The first problem of `markup` read as XML (SVG; HTML when its void elements are listed): a tag
// left open or closed out of order, an attribute value without quotes, a '<' inside a tag or an
// '&' that starts no entity; empty when there is none. Not a full parser: enough for the markup
// the renderers emit.
inline std::string markup_problem(const std::string& markup, const std::set<std::string>& void_elements = {}) {
  std::vector<std::string> open;
  for (std::size_t i = 0; i < markup.size();) {
    if (markup[i] == '&') {
      const std::size_t end = markup.find(';', i);
      if (end == std::string::npos || end - i > 8) return "bare & at " + std::to_string(i);
      for (std::size_t k = i + 1; k < end; ++k) {
        if (!std::isalnum(static_cast<unsigned char>(markup[k])) && markup[k] != '#') return "bad entity at " + std::to_string(i);
      }
      i = end + 1;
      continue;
    }
    if (markup[i] != '<') {
      ++i;
      continue;
    }
    const std::size_t end = markup.find('>', i);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(i);
    const std::string tag = markup.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.find('<') != std::string::npos) return "'<' inside <" + tag + ">";
    if (tag.empty()) return "empty tag";
    if (tag[0] == '?' || tag[0] == '!') continue;  // XML declaration, doctype
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name) return "</" + name + "> closes " + (open.empty() ? "nothing" : "<" + open.back() + ">");
      open.pop_back();
      continue;
    }
    for (std::size_t equals = tag.find('='); equals != std::string::npos; equals = tag.find('=', equals + 1)) {
      if (equals + 1 >= tag.size() || tag[equals + 1] != '"') return "unquoted attribute in <" + tag + ">";
      const std::size_t close = tag.find('"', equals + 2);
      if (close == std::string::npos) return "unclosed attribute in <" + tag + ">";
      equals = close;
    }
    const std::string name = tag.substr(0, tag.find_first_of(" /\n"));
    if (tag.back() != '/' && void_elements.count(name) == 0) open.push_back(name);
  }
  return open.empty() ? "" : "<" + open.back() + "> is never closed";
}

inline const std::set<std::string> html_void_elements = {"meta", "img", "br", "link"};

inline std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++count;
  return count;
}

// The tags of element `name` ("<circle ...>") in `markup` from `from` up to `to`.
inline std::vector<std::string> tags_of(const std::string& markup, const std::string& name, std::size_t from = 0,
                                        std::size_t to = std::string::npos) {
  std::vector<std::string> tags;
  const std::string start = "<" + name + " ";
  for (std::size_t at = markup.find(start, from); at != std::string::npos && at < to; at = markup.find(start, at + 1)) {
    tags.push_back(markup.substr(at, markup.find('>', at) - at + 1));
  }
  return tags;
}

// The number in attribute `name` of one tag; NaN when the tag has no such attribute.
inline double number_attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(tag.c_str() + at + key.size(), nullptr);
}

}  // namespace fscil
