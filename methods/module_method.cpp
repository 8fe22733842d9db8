#include "methods/module_method.h"

#include <fmt/format.h>

#include <set>

#include "methods/common/module_state.h"
#include "methods/common/traced_cost.h"

namespace fscil {

void ModuleMethod::build_modules(const RunContext& context) {
  NamedModules built = build(context);
  if (built.empty()) throw MethodError("build() returned no modules");
  std::set<std::string> names;
  std::set<const torch::nn::Module*> objects;
  for (const auto& named : built) {
    if (named.name.empty() || named.module == nullptr) throw MethodError("build() returned a module without a name or an object");
    if (!names.insert(named.name).second) throw MethodError(fmt::format("build() returned two modules named '{}'", named.name));
    for (const auto& part : named.module->modules()) {  // the module itself and everything inside it
      if (!objects.insert(part.get()).second) {
        throw MethodError(fmt::format("build(): '{}' shares a module with another entry: its tensors would count twice",
                                      named.name));
      }
    }
  }
  modules_ = std::move(built);
}

const NamedModules& ModuleMethod::modules() const {
  if (modules_.empty()) throw MethodError("no modules yet: train_base() starts with build_modules(context)");
  return modules_;
}

MethodState ModuleMethod::save_state() const {
  MethodState state;
  for (const auto& named : modules()) put_module(state, named.name + ".", *named.module);
  return state;
}

void ModuleMethod::restore_state(const MethodState& state, RunContext& context) {
  build_modules(context);
  const MethodState expected = save_state();
  for (const auto& entry : state) {
    if (expected.count(entry.first) == 0) {
      throw MethodError(fmt::format("state entry '{}' is none of this method's parameters or buffers", entry.first));
    }
  }
  for (const auto& named : modules_) take_module(state, named.name + ".", *named.module);
}

ModelCost ModuleMethod::inference_cost(const InputShape& input) const {
  const torch::Tensor sample = torch::zeros({1, input.channels, input.mel_bins, input.frames});
  // Tracing runs the method as it stands: in eval mode, so no norm learns from the zeros, and each
  // module's mode restored after. logits() is not const only because embed() and classify() are not.
  std::vector<bool> training;
  for (const auto& named : modules()) {
    training.push_back(named.module->is_training());
    named.module->eval();
  }
  auto& method = const_cast<ModuleMethod&>(*this);
  const ModelCost cost = traced_cost([&] { method.logits(sample); }, modules_);
  for (std::size_t i = 0; i < modules_.size(); ++i) modules_[i].module->train(training[i]);
  return cost;
}

}  // namespace fscil
