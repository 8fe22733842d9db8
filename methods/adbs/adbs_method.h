#pragma once
#include <memory>

#include "methods/adbs/adbs_settings.h"
#include "methods/adbs/decision_boundaries.h"
#include "methods/common/class_count.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

class BestEpoch;

// ADBS, adaptive decision boundaries (Li et al., AAAI 2025; Yongzhang-Tan/ADBS at 756414c3), on
// the shared encoder:
// 1. base: encoder + cosine classifier + one margin per class, CE on the margin-scaled logits
//    plus the inter-class constraint, then every base row becomes its class's mean embedding;
// 2. each session: the encoder is frozen, new rows are the shots' mean embeddings, new margins
//    start at the mean of the earlier ones and alone train for a few steps on the shots.
// Its state is its modules: encoder, classifier rows, margins and the count of seen classes.
class AdbsMethod : public ModuleMethod {
 public:
  explicit AdbsMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  void consider_epoch(BestEpoch& best, int epoch, RunContext& context);
  void record_margins(RunContext& context) const;

  AdbsSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  CosineClassifier classifier_{nullptr};
  DecisionBoundaries boundaries_{nullptr};
  ClassCount seen_classes_{nullptr};
};

MethodEntry adbs_entry();

}  // namespace fscil
