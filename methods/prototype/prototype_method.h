#pragma once
#include <memory>

#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/supervised_training.h"
#include "methods/method.h"

namespace fscil {

// The plain baseline: train encoder + cosine classifier on the base classes, then freeze the
// encoder; every class (base ones too) is represented by its mean normalised embedding.
class PrototypeMethod : public Method {
 public:
  explicit PrototypeMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;
  bool sessions_keep_embedding() const override { return true; }  // sessions only add prototypes
  MethodState save_state() const override;
  void restore_state(const MethodState& state, RunContext& context) override;

 private:
  void build_network(const RunContext& context);
  void add_prototypes(const SessionData& data);

  SupervisedSchedule schedule_;
  double temperature_;
  ResNet18Encoder encoder_{nullptr};
  CosineClassifier classifier_{nullptr};
  std::int64_t seen_classes_ = 0;
};

std::unique_ptr<Method> make_prototype_method(const ParameterSet& params);

}  // namespace fscil
