#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/valid_range.h"

namespace fscil {

// Named hyper-parameters and knobs as text, layered (profile, then --set) and read with a default.
// Every read is remembered, so a result file can hold every value a run used and the CLI can
// reject a --set key that nothing reads.
class ParameterSet {
 public:
  // `origin` names what gave the value when it is not the command line's --set (`--config FILE:
  // "set"`, `rerun FILE: "parameters"`): an error in the value names it, not a flag never typed.
  void set(const std::string& key, const std::string& value, const std::string& origin = "");
  // A value that another replaced before any run could read it (a --config file's, under the
  // command line's): a read of `key` checks its form as it checks the value read (a finite number,
  // an integer that fits, true or false, an allowed choice), so nonsense is refused wherever it was
  // written, named by its origin. Not its range: that may depend on values that replaced others.
  void check_also(const std::string& key, const std::string& value, const std::string& origin);
  // A value a profile or dataset supplies for whichever method reads it: unlike set(), it is not
  // reported by unread_keys() when nothing reads it. A later set() makes it explicit.
  void set_default(const std::string& key, const std::string& value);
  // Parses "key=value"; throws ProtocolError naming the text when malformed.
  void set_assignment(const std::string& assignment, const std::string& origin = "");
  bool contains(const std::string& key) const;

  // Numbers say where they are valid; a value outside `valid` throws ProtocolError naming the key
  // and, for a value not from the command line, its origin.
  double real(const std::string& key, double fallback, const ValidRange& valid) const;
  std::int64_t integer(const std::string& key, std::int64_t fallback, const ValidRange& valid) const;
  // integer() for what an int holds (epochs, sizes, counts): a value beyond int's range is refused,
  // never wrapped.
  int count(const std::string& key, int fallback, const ValidRange& valid) const;
  bool flag(const std::string& key, bool fallback) const;
  std::string text(const std::string& key, const std::string& fallback) const;
  // text() restricted to a list of allowed values.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed) const;

  // Values of every key read so far, as used (defaults included).
  const std::map<std::string, std::string>& used() const { return used_; }
  // Keys set explicitly that no reader asked for.
  std::vector<std::string> unread_keys() const;
  // Marks keys read in another copy as read here too (used when each method reads its own copy).
  void mark_read(const std::set<std::string>& keys);
  std::set<std::string> read_keys() const;

 private:
  const std::string* lookup(const std::string& key) const;
  void remember(const std::string& key, const std::string& value) const;
  std::string origin_of(const std::string& key) const;  // "" for the command line's
  // The values check_also() kept for `key`, each with its origin.
  std::vector<std::pair<std::string, std::string>> replaced_texts(const std::string& key) const;

  std::map<std::string, std::string> values_;
  std::set<std::string> defaults_;  // keys whose value came from set_default()
  std::map<std::string, std::string> origins_;  // key -> what gave its value, where set() was told
  std::multimap<std::string, std::pair<std::string, std::string>> replaced_;  // key -> value, origin
  mutable std::map<std::string, std::string> used_;
};

}  // namespace fscil
