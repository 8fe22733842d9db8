#pragma once
#include "methods/common/named_module.h"
#include "methods/method.h"

namespace fscil {

// A method whose whole trained state lives in a list of named modules (parameters and buffers:
// keep counters such as the classes seen in a buffer too; requires_grad is not state). It writes
// five functions: build(), which creates the modules for a run and returns them by name, and
// train_base(), learn_session(), embed() and classify(); train_base() starts with
// build_modules(context). save_state() and restore_state() then copy the modules' tensors, and
// inference_cost() traces logits() on one sample in eval mode (methods/common/traced_cost.h), so
// embed() and classify() must not draw random numbers. Modules only training needs (a base
// session's head) stay out of the list: they would count as parameters of the model.
class ModuleMethod : public Method {
 public:
  MethodState save_state() const override;
  void restore_state(const MethodState& state, RunContext& context) override;
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  virtual NamedModules build(const RunContext& context) = 0;
  void build_modules(const RunContext& context);
  const NamedModules& modules() const;

 private:
  NamedModules modules_;
};

}  // namespace fscil
