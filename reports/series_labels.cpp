#include "reports/series_labels.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "reports/figure.h"

namespace fscil {

namespace {

std::string label_of(const std::string& method, const GridCell& cell, const std::map<std::string, std::string>& short_keys) {
  std::string assignments;
  for (const auto& [key, value] : cell) {
    const auto shorter = short_keys.find(key);
    assignments += fmt::format("{}{}={}", assignments.empty() ? "" : "+", shorter == short_keys.end() ? key : shorter->second,
                               value);
  }
  if (assignments.empty()) return method;
  return method.empty() ? assignments : fmt::format("{} [{}]", method, assignments);
}

std::vector<std::string> labels_of(const std::vector<SeriesName>& names, const std::map<std::string, std::string>& short_keys) {
  std::vector<std::string> labels;
  for (const auto& name : names) labels.push_back(label_of(name.method, name.cell, short_keys));
  return labels;
}

bool all_fit(const std::vector<std::string>& labels, std::size_t width) {
  return std::all_of(labels.begin(), labels.end(), [&](const std::string& label) { return code_points(label) <= width; });
}

// The shortest prefix of `key`, of 3 characters at least (one would not say which key it is), that
// no other of `keys` starts with; the key itself where it is the start of another.
std::string shortest_prefix(const std::string& key, const std::vector<std::string>& keys) {
  for (std::size_t length = 3; length < key.size(); ++length) {
    const std::string prefix = key.substr(0, length);
    if (std::none_of(keys.begin(), keys.end(),
                     [&](const std::string& other) { return other != key && other.compare(0, length, prefix) == 0; })) {
      return prefix;
    }
  }
  return key;
}

}  // namespace

SeriesLabels series_labels(const std::vector<SeriesName>& names, std::size_t width) {
  SeriesLabels result{labels_of(names, {}), ""};
  if (names.size() < 2 || all_fit(result.labels, width)) return result;

  // What every series shares says nothing about which is which: it goes to the note.
  std::vector<std::string> shared;
  std::vector<SeriesName> varying = names;
  const bool one_method = std::all_of(names.begin(), names.end(),
                                      [&](const SeriesName& name) { return name.method == names.front().method; });
  if (one_method) {
    shared.push_back(names.front().method);
    for (auto& name : varying) name.method.clear();
  }
  std::vector<std::string> keys;  // every key of the figure, in the grid's order
  for (const auto& name : names) add_new_keys(name.cell, keys);
  for (const std::string& key : keys) {
    const std::string* first = grid_value(names.front().cell, key);
    const bool constant = first != nullptr && std::all_of(names.begin(), names.end(), [&](const SeriesName& name) {
                            const std::string* value = grid_value(name.cell, key);
                            return value != nullptr && *value == *first;
                          });
    if (!constant) continue;
    shared.push_back(key + "=" + *first);
    for (auto& name : varying) name.cell = without_key(name.cell, key);
  }
  std::vector<std::string> labels = labels_of(varying, {});
  if (!all_fit(labels, width)) {
    std::map<std::string, std::string> short_keys;
    std::vector<std::string> spelt_out;
    for (const auto& name : varying) {
      for (const auto& entry : name.cell) {
        const std::string& key = entry.first;
        if (short_keys.count(key) > 0) continue;
        short_keys[key] = shortest_prefix(key, keys);
        if (short_keys[key] != key) spelt_out.push_back(fmt::format("{} = {}", short_keys[key], key));
      }
    }
    labels = labels_of(varying, short_keys);
    shared.insert(shared.end(), spelt_out.begin(), spelt_out.end());
  }
  if (std::any_of(labels.begin(), labels.end(), [](const std::string& label) { return label.empty(); })) return result;
  result.labels = std::move(labels);
  result.shared = fmt::format("{}", fmt::join(shared, "; "));
  return result;
}

}  // namespace fscil
