#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "methods/common/class_count.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/ldc/calibration_unit.h"
#include "methods/ldc/distribution_memory.h"
#include "methods/ldc/ldc_settings.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// LDC, learnable distribution calibration (Liu, Yang, Xie, Wang, Tian, Ye, TPAMI 2023), on the
// shared encoder, as its release (Bibikiller/LDC, "final files: to be cleaned") and its abstract
// describe it: no runnable release exists and the paper's text could not be read here, so this is
// our reading, every gap marked (ours) in docs/methods.md, "ldc". The base session pretrains the
// encoder with the cosine classifier (prototype's stage, shared), sets the base rows to the class
// means and keeps one covariance shared by all classes; features drawn from N(mean, shared
// covariance) then train the calibration unit to carry them, by recurrent updates, onto the real
// features' distribution. Each session adds its shots' means as rows, folds their covariances into
// the shared one, draws a few features for each new class, and fine-tunes every seen row on the
// shots and on every class's calibrated draws. The encoder stays frozen after the base session.
class LdcMethod : public ModuleMethod {
 public:
  explicit LdcMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  void forget_classes(const std::vector<std::int64_t>& classes, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  // dis_match over `epochs` (helper.py L68-L83): per base class one step on its drawn features.
  void train_calibration(const torch::Tensor& drawn, const std::vector<torch::Tensor>& real, RunContext& context);
  // update_fc_ft (Network.py): the rows of classes [0, seen) on the shots and the kept draws.
  void finetune_rows(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t seen,
                     RunContext& context);

  LdcSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  CosineClassifier classifier_{nullptr};
  CalibrationUnit calibration_{nullptr};
  DistributionMemory memory_{nullptr};
  ClassCount seen_classes_{nullptr};
};

MethodEntry ldc_entry();

}  // namespace fscil
