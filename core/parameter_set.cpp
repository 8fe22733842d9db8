#include "core/parameter_set.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/error.h"
#include "core/shown_text.h"
#include "core/number_text.h"

namespace fscil {

namespace {

// A value's text names its run (results, sweep cells): "+5" beside "5" would be two cells of one
// value, so parameters take no '+' (data files, read by the same parser, may).
void refuse_plus_sign(const std::string& key, const std::string& value) {
  if (!value.empty() && value.front() == '+') {
    throw ProtocolError(fmt::format("parameter {}='{}': expected the number without '+' (the value's text names the "
                                    "run, and '{}' would be another)", key, shown_text(value), shown_text(value.substr(1))));
  }
}

}  // namespace

void ParameterSet::set(const std::string& key, const std::string& value) {
  values_[key] = value;
  defaults_.erase(key);
}

void ParameterSet::set_default(const std::string& key, const std::string& value) {
  values_[key] = value;
  defaults_.insert(key);
}

void ParameterSet::set_assignment(const std::string& assignment) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw ProtocolError(fmt::format("--set '{}': expected key=value", shown_text(assignment)));
  }
  set(assignment.substr(0, equals), assignment.substr(equals + 1));
}

bool ParameterSet::contains(const std::string& key) const { return values_.count(key) != 0; }

const std::string* ParameterSet::lookup(const std::string& key) const {
  const auto found = values_.find(key);
  return found == values_.end() ? nullptr : &found->second;
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
  refuse_plus_sign(key, *value);
  const auto parsed = parse_finite_number(*value);
  if (!parsed) throw ProtocolError(fmt::format("parameter {}='{}': expected a finite number", key, shown_text(*value)));
  if (!valid.contains(*parsed)) {
    throw ProtocolError(fmt::format("parameter {}='{}': expected a number {}", key, shown_text(*value), valid.describe()));
  }
  // Training runs in float: a value past float's range overflows in the first tensor it meets.
  if (std::abs(*parsed) > std::numeric_limits<float>::max()) {
    throw ProtocolError(fmt::format("parameter {}='{}': expected a number of at most {:g} in magnitude "
                                    "(training runs in 32-bit floats)", key, shown_text(*value), std::numeric_limits<float>::max()));
  }
  remember(key, shown_text(*value));
  return *parsed;
}

std::int64_t ParameterSet::integer(const std::string& key, std::int64_t fallback, const ValidRange& valid) const {
  const std::string* value = lookup(key);
  if (value == nullptr) {
    remember(key, std::to_string(fallback));
    return fallback;
  }
  refuse_plus_sign(key, *value);
  const auto parsed = parse_number<std::int64_t>(*value);
  if (!parsed) throw ProtocolError(fmt::format("parameter {}='{}': expected an integer", key, shown_text(*value)));
  // "05" or "-0" beside "5" or "0" would be another run of one value, as "+5" would.
  if (*value != std::to_string(*parsed)) {
    throw ProtocolError(fmt::format("parameter {}='{}': expected the integer as {} (the value's text names the run)",
                                    key, shown_text(*value), *parsed));
  }
  if (!valid.contains(static_cast<double>(*parsed))) {
    throw ProtocolError(fmt::format("parameter {}='{}': expected an integer {}", key, shown_text(*value), valid.describe()));
  }
  remember(key, shown_text(*value));
  return *parsed;
}

int ParameterSet::count(const std::string& key, int fallback, const ValidRange& valid) const {
  const std::int64_t value = integer(key, fallback, valid);
  if (value > std::numeric_limits<int>::max() || value < std::numeric_limits<int>::min()) {
    throw ProtocolError(fmt::format("parameter {}='{}': expected an integer {} and at most {}", key, value,
                                    valid.describe(), std::numeric_limits<int>::max()));
  }
  return static_cast<int>(value);
}

bool ParameterSet::flag(const std::string& key, bool fallback) const {
  const std::string* value = lookup(key);
  if (value == nullptr) {
    remember(key, fallback ? "true" : "false");
    return fallback;
  }
  if (*value == "true" || *value == "1" || *value == "on") {
    remember(key, "true");
    return true;
  }
  if (*value == "false" || *value == "0" || *value == "off") {
    remember(key, "false");
    return false;
  }
  throw ProtocolError(fmt::format("parameter {}='{}': expected true or false", key, shown_text(*value)));
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
  if (std::find(allowed.begin(), allowed.end(), result) == allowed.end()) {
    throw ProtocolError(
        fmt::format("parameter {}='{}': expected one of {}", key, shown_text(result), fmt::join(allowed, ", ")));
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
