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
std::vector<MethodEntry>& registry() {
  static std::vector<MethodEntry> table = {
      {"prototype", "cosine classifier trained on base classes, frozen encoder, class-mean prototypes",
       &make_prototype_method},
      {"pits-sc", "PITS-SC: CutMix pretraining, pseudo-incremental training on raw-signal mixtures, stochastic "
       "classifier fine-tuned per session", &make_pits_sc_method},
      {"cop-fscil/cpi", "CoP-FSCIL ablation: pits-sc with context-probing intervention in pseudo-incremental episodes",
       &make_cop_fscil_cpi},
      {"cop-fscil/cpi+pspc", "CoP-FSCIL ablation: CPI plus probe-stability prototype calibration in sessions",
       &make_cop_fscil_cpi_pspc},
      {"cop-fscil/cpi+pcqa", "CoP-FSCIL ablation: CPI plus the probe-conditioned quotient adapter with L_PIC",
       &make_cop_fscil_cpi_pcqa},
      {"cop-fscil", "CoP-FSCIL: CPI, PCQA with L_PIC, and PSPC on the pits-sc stages", &make_cop_fscil},
      {"orco", "OrCo-style: pseudo-targets, Hungarian assignment, projector trained with SupCon, orthogonality and "
       "CE; replays 5 exemplars per base class and every earlier shot", &make_orco_method},
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
  if (entry.name == "all" || entry.name == "ablation") {
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
  if (request == "ablation") return {"pits-sc", "cop-fscil/cpi", "cop-fscil/cpi+pspc", "cop-fscil/cpi+pcqa", "cop-fscil"};
  std::stringstream stream(request);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (find_method(name) == nullptr) {
      throw MethodError(fmt::format("unknown method '{}': expected all, ablation or one of {}", name, known_names()));
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) {
      throw MethodError(fmt::format("--methods {}: '{}' is named twice", request, name));
    }
    names.push_back(name);
  }
  if (names.empty()) throw MethodError(fmt::format("no method named: expected all, ablation or one of {}", known_names()));
  return names;
}

std::unique_ptr<Method> create_method(const std::string& name, const ParameterSet& params) {
  const MethodEntry* entry = find_method(name);
  if (entry == nullptr) throw MethodError(fmt::format("unknown method '{}': expected one of {}", name, known_names()));
  return entry->create(params);
}

}  // namespace fscil
