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

// The first number of the JSON `text` written as nonzero that a double holds as 0 ("1e-400"), or
// nothing: the library keeps 0 without a word (a number too large for a double is its own error).
inline std::optional<std::string> number_read_as_zero(const std::string& text) {
  struct Numbers : nlohmann::json_sax<nlohmann::json> {
    std::optional<std::string> found;
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t value, const string_t& written) override {
      const std::string mantissa = written.substr(0, written.find_first_of("eE"));
      if (value == 0 && !found && mantissa.find_first_of("123456789") != std::string::npos) found = written;
      return true;
    }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return true; }
    bool key(string_t&) override { return true; }
    bool end_object() override { return true; }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
  } numbers;
  nlohmann::json::sax_parse(text, &numbers);
  return numbers.found;
}

}  // namespace fscil
