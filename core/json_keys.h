#pragma once
#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace fscil {

// The first key that appears twice in one object of the JSON `text`, or nothing (also for text that
// is not JSON: its parser says what is wrong). nlohmann::json keeps the last of two equal keys
// without a word, so a value the user wrote would be silently replaced.
inline std::optional<std::string> duplicated_json_key(const std::string& text) {
  using Event = nlohmann::json::parse_event_t;
  std::vector<std::set<std::string>> open_objects;
  std::optional<std::string> duplicated;
  const nlohmann::json::parser_callback_t note = [&](int, Event event, nlohmann::json& parsed) {
    if (event == Event::object_start) {
      open_objects.emplace_back();
    } else if (event == Event::object_end && !open_objects.empty()) {
      open_objects.pop_back();
    } else if (event == Event::key && !open_objects.empty() && !duplicated &&
               !open_objects.back().insert(parsed.get<std::string>()).second) {
      duplicated = parsed.get<std::string>();
    }
    return true;
  };
  const nlohmann::json ignored = nlohmann::json::parse(text, note, /*allow_exceptions=*/false);
  return duplicated;
}

}  // namespace fscil
