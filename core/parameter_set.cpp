#include "core/parameter_set.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

#include "core/error.h"
#include "core/shown_text.h"
#include "core/number_text.h"

namespace fscil {

namespace {

// How an error line names a value: "parameter k='v'" for the command line's, "ORIGIN.k='v'" for a
// file's.
std::string named(const std::string& key, const std::string& value, const std::string& origin) {
  if (origin.empty()) return fmt::format("parameter {}='{}'", key, shown_text(value));
  return fmt::format("{}.{}='{}'", origin, shown_text(key), shown_text(value));
}

// A value's text names its run (results, sweep cells): "+5" beside "5" would be two cells of one
// value, so parameters take no '+' (data files, read by the same parser, may).
void refuse_plus_sign(const std::string& key, const std::string& value, const std::string& origin) {
  if (!value.empty() && value.front() == '+') {
    throw ProtocolError(fmt::format("{}: expected the number without '+' (the value's text names the run, and '{}' "
                                    "would be another)", named(key, value, origin), shown_text(value.substr(1))));
  }
}

double real_of(const std::string& key, const std::string& value, const std::string& origin, const ValidRange& valid) {
  refuse_plus_sign(key, value, origin);
  const auto parsed = parse_finite_number(value);
  if (!parsed) throw ProtocolError(fmt::format("{}: expected a finite number", named(key, value, origin)));
  if (!valid.contains(*parsed)) {
    throw ProtocolError(fmt::format("{}: expected a number {}", named(key, value, origin), valid.describe()));
  }
  // Training runs in float: a value past float's range overflows in the first tensor it meets.
  if (std::abs(*parsed) > std::numeric_limits<float>::max()) {
    throw ProtocolError(fmt::format("{}: expected a number of at most {:g} in magnitude (training runs in 32-bit "
                                    "floats)", named(key, value, origin), std::numeric_limits<float>::max()));
  }
  return *parsed;
}

std::int64_t integer_of(const std::string& key, const std::string& value, const std::string& origin,
                        const ValidRange& valid) {
  refuse_plus_sign(key, value, origin);
  const auto parsed = parse_number<std::int64_t>(value);
  if (!parsed) throw ProtocolError(fmt::format("{}: expected an integer", named(key, value, origin)));
  // "05" or "-0" beside "5" or "0" would be another run of one value, as "+5" would.
  if (value != std::to_string(*parsed)) {
    throw ProtocolError(fmt::format("{}: expected the integer as {} (the value's text names the run)",
                                    named(key, value, origin), *parsed));
  }
  if (!valid.contains(static_cast<double>(*parsed))) {
    throw ProtocolError(fmt::format("{}: expected an integer {}", named(key, value, origin), valid.describe()));
  }
  return *parsed;
}

std::optional<bool> flag_of(const std::string& value) {
  if (value == "true" || value == "1" || value == "on") return true;
  if (value == "false" || value == "0" || value == "off") return false;
  return std::nullopt;
}

}  // namespace

void ParameterSet::set(const std::string& key, const std::string& value, const std::string& origin) {
  values_[key] = value;
  defaults_.erase(key);
  if (origin.empty()) {
    origins_.erase(key);
  } else {
    origins_[key] = origin;
  }
}

void ParameterSet::set_default(const std::string& key, const std::string& value) {
  values_[key] = value;
  defaults_.insert(key);
  origins_.erase(key);
}

void ParameterSet::check_also(const std::string& key, const std::string& value, const std::string& origin) {
  replaced_.emplace(key, std::make_pair(value, origin));
}

void ParameterSet::set_assignment(const std::string& assignment, const std::string& origin) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw ProtocolError(fmt::format("--set '{}': expected key=value", shown_text(assignment)));
  }
  set(assignment.substr(0, equals), assignment.substr(equals + 1), origin);
}

bool ParameterSet::contains(const std::string& key) const { return values_.count(key) != 0; }

const std::string* ParameterSet::lookup(const std::string& key) const {
  const auto found = values_.find(key);
  return found == values_.end() ? nullptr : &found->second;
}

std::string ParameterSet::origin_of(const std::string& key) const {
  const auto origin = origins_.find(key);
  return origin == origins_.end() ? "" : origin->second;
}

std::vector<std::pair<std::string, std::string>> ParameterSet::replaced_texts(const std::string& key) const {
  std::vector<std::pair<std::string, std::string>> texts;
  const auto [first, last] = replaced_.equal_range(key);
  for (auto it = first; it != last; ++it) texts.push_back(it->second);
  return texts;
}

void ParameterSet::remember(const std::string& key, const std::string& value) const {
  used_[key] = value;
}

double ParameterSet::real(const std::string& key, double fallback, const ValidRange& valid) const {
  const std::string* value = lookup(key);
  if (value == nullptr) {
    remember(key, fmt::format("{}", fallback));
    return fallback;
  }
  // A replaced value's form only: its range may depend on values that replaced others.
  for (const auto& [text, origin] : replaced_texts(key)) real_of(key, text, origin, ValidRange::any());
  const double parsed = real_of(key, *value, origin_of(key), valid);
  remember(key, shown_text(*value));
  return parsed;
}

std::int64_t ParameterSet::integer(const std::string& key, std::int64_t fallback, const ValidRange& valid) const {
  const std::string* value = lookup(key);
  if (value == nullptr) {
    remember(key, std::to_string(fallback));
    return fallback;
  }
  for (const auto& [text, origin] : replaced_texts(key)) integer_of(key, text, origin, ValidRange::any());
  const std::int64_t parsed = integer_of(key, *value, origin_of(key), valid);
  remember(key, shown_text(*value));
  return parsed;
}

int ParameterSet::count(const std::string& key, int fallback, const ValidRange& valid) const {
  const std::int64_t value = integer(key, fallback, valid);
  const auto refuse_past_int = [&](std::int64_t number, const std::string& text, const std::string& origin) {
    if (number > std::numeric_limits<int>::max() || number < std::numeric_limits<int>::min()) {
      throw ProtocolError(fmt::format("{}: expected an integer {} and at most {}", named(key, text, origin),
                                      valid.describe(), std::numeric_limits<int>::max()));
    }
  };
  for (const auto& [text, origin] : replaced_texts(key)) {
    refuse_past_int(integer_of(key, text, origin, ValidRange::any()), text, origin);
  }
  if (const std::string* text = lookup(key)) refuse_past_int(value, *text, origin_of(key));  // a fallback is an int
  return static_cast<int>(value);
}

bool ParameterSet::flag(const std::string& key, bool fallback) const {
  if (lookup(key) == nullptr) {
    remember(key, fallback ? "true" : "false");
    return fallback;
  }
  auto texts = replaced_texts(key);
  texts.emplace_back(*lookup(key), origin_of(key));  // the value read last
  std::optional<bool> parsed;
  for (const auto& [text, origin] : texts) {
    parsed = flag_of(text);
    if (!parsed) throw ProtocolError(fmt::format("{}: expected true or false", named(key, text, origin)));
  }
  remember(key, *parsed ? "true" : "false");
  return *parsed;
}

std::string ParameterSet::text(const std::string& key, const std::string& fallback) const {
  const std::string* value = lookup(key);
  const std::string result = value == nullptr ? fallback : *value;
  remember(key, result);
  return result;
}

std::string ParameterSet::choice(const std::string& key, const std::string& fallback,
                                 const std::vector<std::string>& allowed) const {
  const std::string result = text(key, fallback);
  auto texts = replaced_texts(key);
  texts.emplace_back(result, lookup(key) == nullptr ? "" : origin_of(key));
  for (const auto& [text, origin] : texts) {
    if (std::find(allowed.begin(), allowed.end(), text) == allowed.end()) {
      throw ProtocolError(fmt::format("{}: expected one of {}", named(key, text, origin), fmt::join(allowed, ", ")));
    }
  }
  return result;
}

std::vector<std::string> ParameterSet::unread_keys() const {
  std::vector<std::string> unread;
  for (const auto& [key, value] : values_) {
    if (used_.count(key) == 0 && defaults_.count(key) == 0) unread.push_back(key);
  }
  return unread;
}

void ParameterSet::mark_read(const std::set<std::string>& keys) {
  for (const auto& key : keys) {
    if (const std::string* value = lookup(key)) remember(key, shown_text(*value));
  }
}

std::set<std::string> ParameterSet::read_keys() const {
  std::set<std::string> keys;
  for (const auto& [key, value] : used_) keys.insert(key);
  return keys;
}

}  // namespace fscil
