#pragma once
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/json_depth.h"
#include "core/json_keys.h"
#include "core/shown_text.h"
#include "core/valid_range.h"

namespace fscil {

// What the JSON library says, without its "[json.exception.parse_error.101] " prefix: a message
// for a user, not a library's error code.
inline std::string json_error_text(const nlohmann::json::exception& error) {
  std::string text = error.what();
  if (text.rfind("[json.exception.", 0) == 0) {
    if (const auto close = text.find("] "); close != std::string::npos) text = text.substr(close + 2);
  }
  return text;
}

// Whether `value` is a whole number from `least` that fits T: what a reader checks before get<T>(),
// which would convert 1e300 or -1.5 with undefined behaviour.
template <typename T>
bool fits_whole_number(const nlohmann::json& value, T least) {
  constexpr auto most = static_cast<std::uint64_t>(std::numeric_limits<T>::max());
  const auto from_least = [least](std::uint64_t number) {
    if constexpr (std::is_signed_v<T>) {
      if (least < 0) return true;
    }
    return number >= static_cast<std::uint64_t>(least);
  };
  if (value.is_number_unsigned()) {
    const auto number = value.template get<std::uint64_t>();
    return number <= most && from_least(number);
  }
  if (value.is_number_integer()) {
    const auto number = value.template get<std::int64_t>();
    return number < 0 ? std::is_signed_v<T> && number >= static_cast<std::int64_t>(least)
                      : static_cast<std::uint64_t>(number) <= most && from_least(static_cast<std::uint64_t>(number));
  }
  return false;
}

// An error E naming `origin` when `text` nests arrays and objects past kDeepestJson (json_depth.h):
// checked before any parse. `expected` says what the file should be.
template <typename E>
void refuse_deep_json(const std::string& text, const std::string& origin, const std::string& expected) {
  if (json_nests_deeper_than(text, kDeepestJson)) {
    throw E(fmt::format("{}: arrays and objects nested more than {} deep, expected {}", origin, kDeepestJson, expected));
  }
}

// An error E naming `origin` when a number of the JSON `text` is written nonzero but too small for
// a double, which the library reads as 0 without a word.
template <typename E>
void refuse_number_read_as_zero(const std::string& text, const std::string& origin) {
  if (const auto number = number_read_as_zero(text)) {
    throw E(fmt::format("{}: the number {} is too small for a double (it would be read as 0); write 0 or a larger "
                        "number", origin, shown_text(*number)));
  }
}

// The text of a JSON file as one object, read strictly: text that is not JSON, a key given twice in
// one object (the library would keep the last without a word) or a top level that is not an object
// is an error E naming `origin`, and so is a number too small for a double.
template <typename E>
nlohmann::json parse_json_object(const std::string& text, const std::string& origin) {
  nlohmann::json document;
  refuse_deep_json<E>(text, origin, "a fscil-bench file");
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw E(fmt::format("{}: not JSON ({})", origin, json_error_text(error)));
  }
  if (const auto key = duplicated_json_key(text)) {
    throw E(fmt::format("{}: field '{}' given twice in one object; give it once", origin, shown_text(*key)));
  }
  refuse_number_read_as_zero<E>(text, origin);
  if (!document.is_object()) throw E(fmt::format("{}: expected a JSON object", origin));
  return document;
}

// The fields of one object of a JSON file, read strictly, each failure an error E in one shape:
//   "{origin}: field '{name}': expected {what}" (a wrong type or value),
//   "{origin}: field '{name}' missing, expected {what}",
//   "{origin}: unknown field '{name}', expected one of a, b, c",
// where name is the field's path from the top ("inference.macs"). The reader of result files,
// dataset.json and configs alike; no message of the JSON library reaches a user.
template <typename E>
class JsonFields {
 public:
  JsonFields(const nlohmann::json& object, std::string origin, std::string path = "")
      : object_(object), origin_(std::move(origin)), path_(std::move(path)) {
    if (!object_.is_object()) throw E(fmt::format("{}: field '{}': expected an object", origin_, path_));
  }

  bool has(const std::string& key) const { return object_.contains(key); }

  const nlohmann::json& at(const std::string& key, const char* expected) const {
    if (!has(key)) throw E(fmt::format("{}: field '{}' missing, expected {}", origin_, name(key), expected));
    return object_.at(key);
  }

  std::string text(const std::string& key) const {
    const auto& value = at(key, "a string");
    if (!value.is_string()) fail(key, "a string, found " + shown_text(value.dump()));
    return value.template get<std::string>();
  }
  std::string text(const std::string& key, const std::string& fallback) const { return has(key) ? text(key) : fallback; }

  double number(const std::string& key, const ValidRange& valid = ValidRange::any()) const {
    const auto& value = at(key, "a number");
    if (!value.is_number() || !valid.contains(value.template get<double>())) {
      fail(key, "a number " + valid.describe() + ", found " + shown_text(value.dump()));
    }
    return value.template get<double>();
  }

  double number(const std::string& key, const ValidRange& valid, double fallback) const {
    return has(key) ? number(key, valid) : fallback;
  }

  // A whole number in `valid` (an int64).
  std::int64_t integer(const std::string& key, const ValidRange& valid) const {
    const auto& value = at(key, "an integer");
    if (!fits_whole_number<std::int64_t>(value, std::numeric_limits<std::int64_t>::min()) ||
        !valid.contains(static_cast<double>(value.template get<std::int64_t>()))) {
      fail(key, "an integer " + valid.describe() + ", found " + shown_text(value.dump()));
    }
    return value.template get<std::int64_t>();
  }
  std::int64_t integer(const std::string& key, const ValidRange& valid, std::int64_t fallback) const {
    return has(key) ? integer(key, valid) : fallback;
  }

  bool flag(const std::string& key, bool fallback) const {
    if (!has(key)) return fallback;
    const auto& value = object_.at(key);
    if (!value.is_boolean()) fail(key, "true or false, found " + shown_text(value.dump()));
    return value.template get<bool>();
  }

  // A non-empty list of distinct, non-empty names.
  std::vector<std::string> names(const std::string& key) const {
    const auto& list = at(key, "a list of names");
    if (!list.is_array() || list.empty()) fail(key, "a non-empty list of names, found " + shown_text(list.dump()));
    std::vector<std::string> result;
    for (const auto& item : list) {
      if (!item.is_string() || item.template get<std::string>().empty()) {
        fail(key, "a list of names, found " + shown_text(item.dump()));
      }
      const std::string name = item.template get<std::string>();
      if (std::find(result.begin(), result.end(), name) != result.end()) {
        fail(key, fmt::format("a list of distinct names ('{}' is listed twice)", shown_text(name)));
      }
      result.push_back(name);
    }
    return result;
  }

  // A whole number from `least` that fits T (get<T>() would convert 1e300 or -1.5 with undefined
  // behaviour).
  template <typename T>
  T whole(const std::string& key, T least = std::numeric_limits<T>::min()) const {
    const auto& value = at(key, "a whole number");
    if (!fits_whole_number<T>(value, least)) {
      fail(key, fmt::format("a whole number from {} to {}, found {}", least, std::numeric_limits<T>::max(),
                            shown_text(value.dump())));
    }
    return value.template get<T>();
  }

  // An object of strings ({"shot": "5"}): numbers or lists among its values are refused.
  std::map<std::string, std::string> texts(const std::string& key) const {
    std::map<std::string, std::string> values;
    for (const auto& [name, value] : object(key).object_.items()) {
      if (!value.is_string()) fail(key + "." + name, "a string, found " + shown_text(value.dump()));
      values[name] = value.template get<std::string>();
    }
    return values;
  }

  // An optional object: absent, it reads as one with no fields.
  JsonFields section(const std::string& key) const {
    static const nlohmann::json no_fields = nlohmann::json::object();
    return has(key) ? object(key) : JsonFields(no_fields, origin_, name(key));
  }

  JsonFields object(const std::string& key) const {
    const auto& value = at(key, "an object");
    if (!value.is_object()) fail(key, "an object, found " + shown_text(value.dump()));
    return JsonFields(value, origin_, name(key));
  }

  // A misspelt or foreign field would be ignored without a word: every key must be one of `known`.
  void require_known_keys(const std::vector<std::string>& known) const {
    for (const auto& [key, value] : object_.items()) {
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        throw E(fmt::format("{}: unknown field '{}', expected one of {}", origin_, name(shown_text(key)),
                            fmt::join(known, ", ")));
      }
    }
  }

  [[noreturn]] void fail(const std::string& key, const std::string& expected) const {
    throw E(fmt::format("{}: field '{}': expected {}", origin_, name(key), expected));
  }

  const nlohmann::json& json() const { return object_; }
  const std::string& origin() const { return origin_; }

 private:
  std::string name(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  const nlohmann::json& object_;
  std::string origin_;
  std::string path_;
};

}  // namespace fscil
