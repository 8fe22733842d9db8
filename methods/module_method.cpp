#include "methods/module_method.h"

#include <fmt/format.h>

#include <algorithm>

#include "methods/common/module_state.h"

namespace fscil {

void ModuleMethod::build_modules(const RunContext& context) {
  modules_ = build(context);
  for (const auto& [name, module] : modules_) {
    if (name.empty() || module == nullptr) throw MethodError("build() returned a module without a name or an object");
  }
}

const NamedModules& ModuleMethod::modules() const {
  if (modules_.empty()) throw MethodError("no modules yet: train_base() starts with build_modules(context)");
  return modules_;
}

MethodState ModuleMethod::save_state() const {
  MethodState state;
  for (const auto& [name, module] : modules()) put_module(state, name + ".", *module);
  return state;
}

void ModuleMethod::restore_state(const MethodState& state, RunContext& context) {
  build_modules(context);
  for (const auto& [name, module] : modules_) take_module(state, name + ".", *module);
  for (const auto& [key, tensor] : state) {
    const bool known = std::any_of(modules_.begin(), modules_.end(),
                                   [&](const auto& named) { return key.rfind(named.first + ".", 0) == 0; });
    if (!known) throw MethodError(fmt::format("state entry '{}' belongs to none of this method's modules", key));
  }
}

ModelCost ModuleMethod::inference_cost(const InputShape& input) const {
  const torch::Tensor sample = torch::zeros({1, input.channels, input.mel_bins, input.frames});
  // Tracing runs the method as it stands, without changing it: logits() is not const only because
  // embed() and classify() are not.
  auto& method = const_cast<ModuleMethod&>(*this);
  return traced_cost([&] { method.logits(sample); }, modules());
}

}  // namespace fscil
