#include "methods/method_registry.h"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "core/shown_text.h"
#include "methods/adbs/adbs_method.h"
#include "methods/amfo/amfo_method.h"
#include "methods/arp/arp_method.h"
#include "methods/comp_fscil/comp_fscil_method.h"
#include "methods/cop_fscil/cop_fscil_method.h"
#include "methods/dsn/dsn_method.h"
#include "methods/ldc/ldc_method.h"
#include "methods/method.h"
#include "methods/orco/orco_method.h"
#include "methods/pa_pct/pa_pct_method.h"
#include "methods/pan/pan_method.h"
#include "methods/pits_sc/pits_sc_method.h"
#include "methods/prototype/prototype_method.h"

namespace fscil {

namespace {

// Each method's folder writes its entry: what the runner, the profiles and the tools need of it.
std::vector<MethodEntry>& registry() {
  static std::vector<MethodEntry> table = [] {
    std::vector<MethodEntry> entries = {prototype_entry(), pits_sc_entry()};
    for (MethodEntry& variant : cop_fscil_entries()) entries.push_back(std::move(variant));
    entries.push_back(orco_entry());
    entries.push_back(adbs_entry());
    entries.push_back(pan_entry());
    entries.push_back(pa_pct_entry());
    entries.push_back(dsn_entry());
    entries.push_back(comp_fscil_entry());
    entries.push_back(arp_entry());
    entries.push_back(amfo_entry());
    entries.push_back(ldc_entry());
    return entries;
  }();
  return table;
}

bool& registry_closed() {
  static bool closed = false;
  return closed;
}

const MethodEntry* find_method(const std::string& name) {
  for (const auto& entry : registry()) {
    if (name == entry.name) return &entry;
  }
  return nullptr;
}

std::string known_names() {
  std::vector<std::string> names;
  for (const auto& entry : registry()) names.emplace_back(entry.name);
  return fmt::format("{}", fmt::join(names, ", "));
}

bool is_group(const std::string& name) {
  return std::any_of(registry().begin(), registry().end(), [&](const MethodEntry& entry) {
    return std::find(entry.groups.begin(), entry.groups.end(), name) != entry.groups.end();
  });
}

// "all", then every group, for messages.
std::string list_names() {
  std::vector<std::string> lists = {"all"};
  for (const auto& entry : registry()) {
    for (const auto& group : entry.groups) {
      if (std::find(lists.begin(), lists.end(), group) == lists.end()) lists.push_back(group);
    }
  }
  return fmt::format("{}", fmt::join(lists, ", "));
}
}  // namespace

const std::vector<MethodEntry>& method_registry() { return registry(); }

void close_method_registry() { registry_closed() = true; }

void register_method(MethodEntry entry) {
  if (registry_closed()) {
    throw MethodError(fmt::format("register_method('{}'): called after the command line started; register first",
                                  entry.name));
  }
  const bool well_formed = !entry.name.empty() && std::all_of(entry.name.begin(), entry.name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '/' || c == '+';
  });
  if (!well_formed) {
    throw MethodError(fmt::format("register_method: '{}' is not a method name: expected a-z, 0-9 and -_/+", entry.name));
  }
  if (entry.name == "all" || is_group(entry.name)) {
    throw MethodError(fmt::format("register_method: '{}' is reserved for a list of methods", entry.name));
  }
  if (find_method(entry.name) != nullptr) {
    throw MethodError(fmt::format("register_method: '{}' is registered already", entry.name));
  }
  if (!entry.create) throw MethodError(fmt::format("register_method: '{}' has no create function", entry.name));
  if (!is_one_line(entry.table_note)) {
    throw MethodError(fmt::format("register_method: '{}' has a table_note of more than one line: a table's footnote "
                                  "is one line without control characters", entry.name));
  }
  registry().push_back(std::move(entry));
}

std::vector<std::string> resolve_method_names(const std::string& request) {
  std::vector<std::string> names;
  if (request == "all") {
    for (const auto& entry : method_registry()) names.emplace_back(entry.name);
    return names;
  }
  if (is_group(request)) {
    for (const auto& entry : method_registry()) {
      if (std::find(entry.groups.begin(), entry.groups.end(), request) != entry.groups.end()) names.push_back(entry.name);
    }
    return names;
  }
  if (!request.empty() && request.back() == ',') {  // getline drops an empty last item
    throw MethodError(fmt::format("--methods {}: an empty name after the last comma", request));
  }
  std::stringstream stream(request);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (name == "all" || is_group(name)) {
      throw MethodError(fmt::format("--methods {}: '{}' stands alone (it names its methods itself)", request, name));
    }
    if (find_method(name) == nullptr) {
      throw MethodError(fmt::format("unknown method '{}': expected {} or one of {}", name, list_names(), known_names()));
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      throw MethodError(fmt::format("--methods {}: '{}' is named twice", request, name));
    }
    names.push_back(name);
  }
  if (names.empty()) throw MethodError(fmt::format("no method named: expected {} or one of {}", list_names(), known_names()));
  return names;
}

const MethodEntry& method_entry(const std::string& name) {
  const MethodEntry* entry = find_method(name);
  if (entry == nullptr) throw MethodError(fmt::format("unknown method '{}': expected one of {}", name, known_names()));
  return *entry;
}

std::unique_ptr<Method> create_method(const std::string& name, const ParameterSet& params) {
  return method_entry(name).create(params);
}

}  // namespace fscil
