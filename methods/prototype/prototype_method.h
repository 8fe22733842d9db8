#pragma once
#include <memory>

#include "methods/common/class_count.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/supervised_training.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// The plain baseline: train encoder + cosine classifier on the base classes, then freeze the
// encoder; every class (base ones too) is represented by its mean normalised embedding. Its state
// is its modules (ModuleMethod): the encoder, the classifier's rows and the count of seen classes.
class PrototypeMethod : public ModuleMethod {
 public:
  // Its encoder and cosine classifier as train_supervised() leaves them: ldc's base starts alike
  // (MethodEntry::shared_stages).
  static constexpr const char* kPretrainingStage = "cosine pretraining";
  // That stage, taken from RunContext::stages or trained and filed there; and its work for plan.
  // Both methods that share it go through these, so that it is one stage.
  static void pretrain(ResNet18Encoder& encoder, CosineClassifier& classifier, const SessionData& base,
                       const SupervisedSchedule& schedule, RunContext& context);
  static StageWork pretraining_stage_work(const ParameterSet& read, const RunSizes& sizes);

  explicit PrototypeMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  // Walked, as the other built-in methods' costs are, rather than traced: a trace counts the
  // encoder's input norm as element-wise work, the walk as a norm (metrics/model_cost.h), and the
  // cost tables compare the methods by the same rules.
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  void add_prototypes(const SessionData& data);

  SupervisedSchedule schedule_;
  double temperature_;
  ResNet18Encoder encoder_{nullptr};
  CosineClassifier classifier_{nullptr};
  ClassCount seen_classes_{nullptr};
};

MethodEntry prototype_entry();

}  // namespace fscil
