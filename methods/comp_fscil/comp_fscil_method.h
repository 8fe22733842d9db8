#pragma once
#include <memory>

#include "methods/common/class_count.h"
#include "methods/common/resnet18.h"
#include "methods/comp_fscil/comp_settings.h"
#include "methods/comp_fscil/prototype_set.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// Comp-FSCIL, compositional few-shot class-incremental learning (Zou et al., ICML 2024;
// Zoilsen/Comp-FSCIL), on the shared encoder. A class is a vector row and a set of primitives (a
// map prototype); a sample is scored by a vector head on its pooled embedding plus the CKA
// similarity of its last map's primitives with each class's. The base session trains the encoder
// and both prototype sets with a third loss that scores each sample against base prototypes
// rebuilt from the other classes' primitives ("primitive reuse"). Each session freezes the encoder
// and fine-tunes only the new classes' rows and maps, started at the shots' means.
class CompFscilMethod : public ModuleMethod {
 public:
  explicit CompFscilMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  // The flattened last map (D x h x w per sample): the CKA head needs every position.
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  // The test-time logits of `maps` over the first `classes` classes (helper.py L253-L300).
  torch::Tensor test_logits(const torch::Tensor& maps, std::int64_t classes) const;
  torch::Tensor rows_of(std::int64_t classes) const;
  torch::Tensor maps_of(std::int64_t classes) const;

  CompSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  PrototypeSet base_{nullptr};   // the base classes' rows and maps
  PrototypeSet novel_{nullptr};  // every later class's, written by the sessions
  LearnedScale map_temperature_{nullptr};
  ClassCount seen_classes_{nullptr};
  std::int64_t base_classes_ = 0;
  std::vector<std::int64_t> map_shape_;  // D, h, w
};

MethodEntry comp_fscil_entry();

}  // namespace fscil
