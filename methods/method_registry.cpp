#include "methods/method_registry.h"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "methods/cop_fscil/cop_fscil_method.h"
#include "methods/method.h"
#include "methods/orco/orco_method.h"
#include "methods/pits_sc/pits_sc_method.h"
#include "methods/prototype/prototype_method.h"

namespace fscil {

namespace {

// The profiles' schedules, per stage. fast and smoke shrink epochs (and the learning-rate step with
// them, so the decay still happens) and nothing else.
// The shared supervised pretraining (methods/common/supervised_training.h).
std::map<std::string, ParameterDefaults> pretraining_profiles() {
  return {{"smoke", {{"pretrain_epochs", "3"}, {"lr_step", "2"}}}, {"fast", {{"pretrain_epochs", "8"}, {"lr_step", "4"}}}};
}

// Pretraining, then PITS-SC's pseudo-incremental stage and session fine-tuning (pits-sc and the
// cop-fscil variants).
std::map<std::string, ParameterDefaults> pits_sc_profiles() {
  auto profiles = pretraining_profiles();
  profiles["smoke"].insert(profiles["smoke"].end(), {{"pit_epochs", "1"}, {"pit_episodes", "4"}, {"epochs_new", "20"}});
  profiles["fast"].insert(profiles["fast"].end(), {{"pit_epochs", "2"}});
  return profiles;
}

// Pretraining, then OrCo's projector stage as PITS-SC's second stage is shortened (10 epochs: 2 in
// fast, 1 in smoke), and in smoke its sessions as PITS-SC's are (a tenth: 10 epochs, 1 of warm-up).
std::map<std::string, ParameterDefaults> orco_profiles() {
  auto profiles = pretraining_profiles();
  profiles["smoke"].insert(profiles["smoke"].end(),
                           {{"orco_base_epochs", "1"}, {"orco_session_epochs", "10"}, {"orco_session_warmup", "1"}});
  profiles["fast"].insert(profiles["fast"].end(), {{"orco_base_epochs", "2"}});
  return profiles;
}

std::vector<MethodEntry>& registry() {
  static const std::vector<std::string> ablation = {"ablation"};
  static const std::vector<std::string> pretraining = {"pretrain_epochs"};
  static const std::vector<std::string> pits_sc_stages = {"pretrain_epochs", "pit_epochs"};
  static std::vector<MethodEntry> table = {
      {"prototype", "cosine classifier trained on base classes, frozen encoder, class-mean prototypes",
       &make_prototype_method, {}, pretraining, pretraining_profiles()},
      {"pits-sc", "PITS-SC: CutMix pretraining, pseudo-incremental training on raw-signal mixtures, stochastic "
       "classifier fine-tuned per session", &make_pits_sc_method, ablation, pits_sc_stages, pits_sc_profiles()},
      {"cop-fscil/cpi", "CoP-FSCIL ablation: pits-sc with context-probing intervention in pseudo-incremental episodes",
       &make_cop_fscil_cpi, ablation, pits_sc_stages, pits_sc_profiles()},
      {"cop-fscil/cpi+pspc", "CoP-FSCIL ablation: CPI plus probe-stability prototype calibration in sessions",
       &make_cop_fscil_cpi_pspc, ablation, pits_sc_stages, pits_sc_profiles()},
      {"cop-fscil/cpi+pcqa", "CoP-FSCIL ablation: CPI plus the probe-conditioned quotient adapter with L_PIC",
       &make_cop_fscil_cpi_pcqa, ablation, pits_sc_stages, pits_sc_profiles()},
      {"cop-fscil", "CoP-FSCIL: CPI, PCQA with L_PIC, and PSPC on the pits-sc stages", &make_cop_fscil, ablation,
       pits_sc_stages, pits_sc_profiles()},
      {"orco", "OrCo-style: pseudo-targets, Hungarian assignment, projector trained with SupCon, orthogonality and "
       "CE; replays 5 exemplars per base class and every earlier shot", &make_orco_method, {},
       {"pretrain_epochs", "orco_base_epochs"}, orco_profiles()},
  };
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
  std::stringstream stream(request);
  std::string name;
  while (std::getline(stream, name, ',')) {
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
